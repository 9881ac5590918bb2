#include "core/thermal_identification.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

constexpr std::array<const char*, kThermalParameterCount> kParameterNames = {"R1", "R2", "C1", "C2",
                                                                             "P"};

int index_of(ThermalParameter parameter) {
  return static_cast<int>(parameter);
}

double& value_of(ThermalParameters& p, ThermalParameter parameter) {
  switch (parameter) {
    case ThermalParameter::kR1:
      return p.r1_k_per_w;
    case ThermalParameter::kR2:
      return p.r2_k_per_w;
    case ThermalParameter::kC1:
      return p.c1_j_per_k;
    case ThermalParameter::kC2:
      return p.c2_j_per_k;
    case ThermalParameter::kPower:
      break;
  }
  return p.power_w;
}

std::vector<ThermalParameter> free_parameters(const ThermalParameterMask& mask) {
  std::vector<ThermalParameter> out;
  for (const ThermalParameter p : kThermalParameters) {
    if (mask.is_free(p)) out.push_back(p);
  }
  return out;
}

// Every entry of Eq. 3's augmented matrix [[a, b_power, b_ambient], [0, 0, 0]] is linear in the
// four monomials g1 = 1/(R1 C2), g2 = 1/(R2 C2), h = 1/(R1 C1), f = P/C1.
using Monomials = Eigen::Vector4d;

Monomials monomials(const ThermalParameters& p) {
  return {1.0 / (p.r1_k_per_w * p.c2_j_per_k), 1.0 / (p.r2_k_per_w * p.c2_j_per_k),
          1.0 / (p.r1_k_per_w * p.c1_j_per_k), p.power_w / p.c1_j_per_k};
}

// Exponent of each parameter (columns R1, R2, C1, C2, P) in each monomial (rows g1, g2, h, f):
// ∂m/∂log p = exponent · m, which makes the log-derivatives of Eq. 3 exact.
const Eigen::Matrix<double, 4, kThermalParameterCount>& monomial_exponents() {
  static const Eigen::Matrix<double, 4, kThermalParameterCount> e =
      (Eigen::Matrix<double, 4, kThermalParameterCount>() << -1, 0, 0, -1, 0,  //
       0, -1, 0, -1, 0,                                                        //
       -1, 0, -1, 0, 0,                                                        //
       0, 0, -1, 0, 1)
          .finished();
  return e;
}

// Eq. 3 augmented with its inputs, as a linear function of the monomials.
Eigen::Matrix4d augmented_matrix(const Monomials& m) {
  Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
  a.row(0) << -(m[0] + m[1]), m[0], 0.0, m[1];
  a.row(1) << m[2], -m[2], m[3], 0.0;
  return a;
}

// The zero-order hold of Eq. 3 over one step and its derivatives with respect to the free
// log-parameters: d exp(M T) = upper-right block of exp([[M, dM], [0, M]] T) (Van Loan, 1978).
struct StepSensitivity {
  double step_s = -1.0;
  Eigen::Matrix4d transition;                 // [[Φ, Γ], [0, I]]
  std::vector<Eigen::Matrix4d> d_transition;  // one per free parameter
};

void discretize_with_derivatives(const Eigen::Matrix4d& m, const std::vector<Eigen::Matrix4d>& dm,
                                 double step_s, StepSensitivity& out) {
  out.step_s = step_s;
  out.transition = (m * step_s).exp();
  out.d_transition.resize(dm.size());
  Eigen::Matrix<double, 8, 8> block = Eigen::Matrix<double, 8, 8>::Zero();
  block.topLeftCorner<4, 4>() = m * step_s;
  block.bottomRightCorner<4, 4>() = m * step_s;
  for (std::size_t i = 0; i < dm.size(); ++i) {
    block.topRightCorner<4, 4>() = dm[i] * step_s;
    const Eigen::Matrix<double, 8, 8> e = block.exp();
    out.d_transition[i] = e.topRightCorner<4, 4>();
  }
}

ThermalParameters with_log_parameters(ThermalParameters base,
                                      const std::vector<ThermalParameter>& free,
                                      const Eigen::VectorXd& log_values) {
  for (std::size_t i = 0; i < free.size(); ++i) {
    value_of(base, free[i]) = std::exp(log_values[static_cast<Eigen::Index>(i)]);
  }
  return base;
}

// The direction of log-parameter space the data do not see, for the error message.
std::string describe_direction(const Eigen::VectorXd& v,
                               const std::vector<ThermalParameter>& free) {
  std::ostringstream out;
  out.precision(2);
  bool first = true;
  for (std::size_t i = 0; i < free.size(); ++i) {
    const double c = v[static_cast<Eigen::Index>(i)];
    if (std::abs(c) < 0.05) continue;
    out << (first ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ")) << std::abs(c) << " log "
        << kParameterNames[static_cast<std::size_t>(index_of(free[i]))];
    first = false;
  }
  return out.str();
}

// The SVD of the Jacobian, or a NumericalError when it is rank-deficient.
Eigen::JacobiSVD<Eigen::MatrixXd> require_identifiable(const Eigen::MatrixXd& jacobian,
                                                       const std::vector<ThermalParameter>& free,
                                                       double min_reciprocal_condition) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double reciprocal_condition = s[0] > 0.0 ? s[s.size() - 1] / s[0] : 0.0;
  if (!(reciprocal_condition >= min_reciprocal_condition)) {
    std::ostringstream msg;
    msg << "the free thermal parameters {";
    for (std::size_t i = 0; i < free.size(); ++i) {
      msg << (i ? ", " : "") << kParameterNames[static_cast<std::size_t>(index_of(free[i]))];
    }
    msg << "} are not identifiable from the case temperatures of this log (reciprocal condition "
        << reciprocal_condition << " of the Jacobian): the prediction does not change along "
        << describe_direction(svd.matrixV().col(s.size() - 1), free)
        << "; fix some of them from the datasheet (e.g. R1 and P, Algorithm 1) or log richer data";
    throw NumericalError(msg.str());
  }
  return svd;
}

// Σ (ŷ_k − y_k)², or +∞ for parameters outside the model's domain or a non-finite prediction,
// so that a wild trial step is rejected rather than raised.
double output_error_cost(const CaseTemperatureLog& log, const ThermalParameters& parameters) {
  for (const double value : thermal_parameter_values(parameters)) {
    if (!(value > 0.0) || !std::isfinite(value)) return std::numeric_limits<double>::infinity();
  }
  const double cost = (predict_case_temperature(log, parameters) - log.case_c).squaredNorm();
  return std::isfinite(cost) ? cost : std::numeric_limits<double>::infinity();
}

void require_fraction(double value, std::string_view name) {
  if (!(value > 0.0 && value <= 1.0)) {
    std::ostringstream msg;
    msg << name << " is " << value << ": it must be in (0, 1]";
    throw InvalidInput(msg.str());
  }
}

void require_comparable(const Eigen::Ref<const Eigen::VectorXd>& predicted,
                        const Eigen::Ref<const Eigen::VectorXd>& measured) {
  require_same_length(predicted.size(), "predicted temperatures", measured.size(),
                      "measured temperatures");
  if (measured.size() == 0) throw InvalidInput("a fit needs at least one sample");
  require_finite(predicted, "predicted temperatures");
  require_finite(measured, "measured temperatures");
}

}  // namespace

const char* thermal_parameter_name(ThermalParameter parameter) {
  return kParameterNames[static_cast<std::size_t>(index_of(parameter))];
}

std::array<double, kThermalParameterCount> thermal_parameter_values(const ThermalParameters& p) {
  return {p.r1_k_per_w, p.r2_k_per_w, p.c1_j_per_k, p.c2_j_per_k, p.power_w};
}

ThermalParameters thermal_parameters_from(const std::array<double, kThermalParameterCount>& v) {
  return {v[0], v[1], v[2], v[3], v[4]};
}

// Algorithm 1, steps 1-4.
ThermalParameters identify_from_datasheet(const DatasheetThermalData& data) {
  ThermalParameters p;
  require_positive(data.r1_k_per_w, "datasheet R1 (r1_k_per_w)");
  p.r1_k_per_w = data.r1_k_per_w;
  if (data.c1_j_per_k) {
    require_positive(*data.c1_j_per_k, "datasheet C1 (c1_j_per_k)");
    p.c1_j_per_k = *data.c1_j_per_k;
  } else {
    require_positive(data.diode_volume_m3, "diode volume (diode_volume_m3)");
    require_positive(data.diode_density_kg_per_m3, "diode density (diode_density_kg_per_m3)");
    require_positive(data.diode_specific_heat_j_per_kg_k,
                     "diode specific heat (diode_specific_heat_j_per_kg_k)");
    p.c1_j_per_k =
        data.diode_volume_m3 * data.diode_density_kg_per_m3 * data.diode_specific_heat_j_per_kg_k;
  }
  require_positive(data.case_mass_kg, "case mass (case_mass_kg)");
  require_positive(data.case_specific_heat_j_per_kg_k,
                   "case specific heat (case_specific_heat_j_per_kg_k)");
  p.c2_j_per_k = data.case_mass_kg * data.case_specific_heat_j_per_kg_k;
  require_positive(data.electrical_power_w, "electrical power (electrical_power_w)");
  require_fraction(data.efficiency, "laser efficiency (efficiency)");
  p.power_w = data.electrical_power_w * data.efficiency;
  require_finite(data.equilibrium_case_c, "equilibrium case temperature");
  require_finite(data.equilibrium_ambient_c, "equilibrium ambient temperature");
  require_fraction(data.equilibrium_power_on_fraction, "equilibrium power on fraction");
  const double rise = data.equilibrium_case_c - data.equilibrium_ambient_c;
  if (!(rise > 0.0)) {
    std::ostringstream msg;
    msg << "the equilibrium case temperature " << data.equilibrium_case_c
        << " °C is not above the ambient " << data.equilibrium_ambient_c
        << " °C: a heated scanner at rest must be warmer than its room (Algorithm 1, step 4)";
    throw InvalidInput(msg.str());
  }
  p.r2_k_per_w = rise / (data.equilibrium_power_on_fraction * p.power_w);
  p.validate();
  return p;
}

bool ThermalParameterMask::is_free(ThermalParameter parameter) const {
  switch (parameter) {
    case ThermalParameter::kR1:
      return r1;
    case ThermalParameter::kR2:
      return r2;
    case ThermalParameter::kC1:
      return c1;
    case ThermalParameter::kC2:
      return c2;
    case ThermalParameter::kPower:
      break;
  }
  return power;
}

int ThermalParameterMask::count() const {
  return static_cast<int>(free_parameters(*this).size());
}

void CaseTemperatureLog::validate() const {
  require_thermal_inputs(power_on_fraction, ambient_c);
  require_same_length(times_s.size(), "log times", power_on_fraction.size(), "power on fractions");
  require_same_length(case_c.size(), "case temperatures", times_s.size(), "log times");
  require_sample_times(times_s);
  require_finite(case_c, "case temperatures");
}

// The output-error predictor of the PEM (§3.2) and §8.1's validation simulation.
Eigen::VectorXd predict_case_temperature(const CaseTemperatureLog& log,
                                         const ThermalParameters& parameters) {
  log.validate();
  const Eigen::Vector2d initial =
      state_at_case_temperature(parameters, log.case_c[0], log.power_on_fraction[0]);
  return simulate_at_times(parameters, initial, log.times_s, log.power_on_fraction, log.ambient_c)
      .case_c;
}

// Sensitivity equations of the zero-order-hold model of Eq. 3:
//   x_{k+1} = Φ x_k + Γ w_k,  S_{k+1} = Φ S_k + ∂Φ x_k + ∂Γ w_k,  w_k = [u_k, t^a_k].
CaseSensitivity case_temperature_sensitivity(const CaseTemperatureLog& log,
                                             const ThermalParameters& parameters,
                                             const ThermalParameterMask& free) {
  log.validate();
  parameters.validate();
  const std::vector<ThermalParameter> names = free_parameters(free);
  const Eigen::Index n = static_cast<Eigen::Index>(names.size());
  const Monomials m = monomials(parameters);
  const Eigen::Matrix4d base = augmented_matrix(m);
  std::vector<Eigen::Matrix4d> derivative;
  for (const ThermalParameter p : names) {
    derivative.push_back(augmented_matrix(monomial_exponents().col(index_of(p)).cwiseProduct(m)));
  }

  const Eigen::Index k = log.times_s.size();
  CaseSensitivity out{Eigen::VectorXd(k), Eigen::MatrixXd(k, n)};
  const double u0 = log.power_on_fraction[0];
  Eigen::Vector4d z;  // [x; w]
  z.head<2>() = state_at_case_temperature(parameters, log.case_c[0], u0);
  // Initial state [y_0, y_0 + u_0 P R1]: its junction depends on log R1 and log P.
  Eigen::Matrix<double, 4, Eigen::Dynamic> s = Eigen::MatrixXd::Zero(4, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const ThermalParameter p = names[static_cast<std::size_t>(i)];
    if (p == ThermalParameter::kR1 || p == ThermalParameter::kPower) {
      s(1, i) = u0 * parameters.power_w * parameters.r1_k_per_w;
    }
  }
  StepSensitivity step;
  for (Eigen::Index t = 0; t < k; ++t) {
    out.predicted_case_c[t] = z[0];
    out.jacobian.row(t) = s.row(0);
    if (t + 1 == k) break;
    const double dt = log.times_s[t + 1] - log.times_s[t];
    if (dt != step.step_s) discretize_with_derivatives(base, derivative, dt, step);
    z[2] = log.power_on_fraction[t];
    z[3] = log.ambient_c[t];
    // The input rows of s are zero (inputs do not depend on the parameters).
    Eigen::Matrix<double, 4, Eigen::Dynamic> next = step.transition * s;
    for (Eigen::Index i = 0; i < n; ++i) {
      next.col(i) += step.d_transition[static_cast<std::size_t>(i)] * z;
    }
    s = next;
    z = step.transition * z;
  }
  return out;
}

// Levenberg–Marquardt on the free log-parameters for the output-error criterion Σ (ŷ_k − y_k)².
PemResult identify_by_prediction_error(const CaseTemperatureLog& log,
                                       const ThermalParameters& initial,
                                       const PemOptions& options) {
  log.validate();
  initial.validate();
  const std::vector<ThermalParameter> names = free_parameters(options.free);
  const Eigen::Index n = static_cast<Eigen::Index>(names.size());
  if (n == 0) throw InvalidInput("the prediction-error method needs at least one free parameter");
  if (log.case_c.size() <= n) {
    std::ostringstream msg;
    msg << "the log has " << log.case_c.size() << " samples for " << n
        << " free parameters: it needs more samples than free parameters";
    throw InvalidInput(msg.str());
  }
  if (options.max_iterations < 1) throw InvalidInput("max_iterations must be at least 1");
  require_positive(options.max_log_step, "max_log_step");
  require_positive(options.min_reciprocal_condition, "min_reciprocal_condition");
  if (!(options.max_relative_std > 0.0)) throw InvalidInput("max_relative_std must be positive");
  if (!(options.step_tolerance >= 0.0) || !(options.relative_cost_tolerance >= 0.0)) {
    throw InvalidInput("PEM tolerances must be non-negative");
  }

  Eigen::VectorXd theta(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    theta[i] = std::log(thermal_parameter_values(
        initial)[static_cast<std::size_t>(index_of(names[static_cast<std::size_t>(i)]))]);
  }
  ThermalParameters current = initial;
  CaseSensitivity sensitivity = case_temperature_sensitivity(log, current, options.free);
  Eigen::VectorXd residual = sensitivity.predicted_case_c - log.case_c;
  double cost = residual.squaredNorm();
  require_identifiable(sensitivity.jacobian, names, options.min_reciprocal_condition);

  PemResult result;
  double damping = 1e-3;
  for (int iteration = 1; iteration <= options.max_iterations && !result.converged; ++iteration) {
    result.iterations = iteration;
    if (cost == 0.0) {
      result.converged = true;
      break;
    }
    const Eigen::MatrixXd normal = sensitivity.jacobian.transpose() * sensitivity.jacobian;
    const Eigen::VectorXd gradient = sensitivity.jacobian.transpose() * residual;
    const Eigen::VectorXd diagonal =
        normal.diagonal().cwiseMax(1e-12 * normal.diagonal().maxCoeff());
    bool accepted = false;
    while (!accepted) {
      Eigen::MatrixXd damped = normal;
      damped.diagonal() += damping * diagonal;
      Eigen::VectorXd step = -damped.ldlt().solve(gradient);
      const double largest = step.cwiseAbs().maxCoeff();
      if (largest > options.max_log_step) step *= options.max_log_step / largest;
      const Eigen::VectorXd trial_theta = theta + step;
      const ThermalParameters trial = with_log_parameters(initial, names, trial_theta);
      const double trial_cost = output_error_cost(log, trial);
      if (trial_cost < cost) {
        accepted = true;
        result.converged = step.cwiseAbs().maxCoeff() < options.step_tolerance ||
                           cost - trial_cost <= options.relative_cost_tolerance * cost;
        theta = trial_theta;
        current = trial;
        cost = trial_cost;
        damping = std::max(damping / 3.0, 1e-12);
        sensitivity = case_temperature_sensitivity(log, current, options.free);
        residual = sensitivity.predicted_case_c - log.case_c;
      } else if ((damping *= 4.0) > 1e16) {
        // No step, however short, lowers the cost: a minimum to working precision.
        result.converged = true;
        break;
      }
    }
  }

  const Eigen::JacobiSVD<Eigen::MatrixXd> svd =
      require_identifiable(sensitivity.jacobian, names, options.min_reciprocal_condition);
  const double noise_variance = cost / static_cast<double>(log.case_c.size() - n);
  const Eigen::MatrixXd v_over_s = svd.matrixV() * svd.singularValues().cwiseInverse().asDiagonal();
  for (Eigen::Index i = 0; i < n; ++i) {
    result.relative_std[static_cast<std::size_t>(index_of(names[static_cast<std::size_t>(i)]))] =
        std::sqrt(noise_variance) * v_over_s.row(i).norm();
  }
  for (const ThermalParameter p : names) {
    const double relative_std = result.relative_std[static_cast<std::size_t>(index_of(p))];
    if (!(relative_std <= options.max_relative_std)) {
      std::ostringstream msg;
      msg << "the log does not determine " << kParameterNames[static_cast<std::size_t>(index_of(p))]
          << ": its relative standard error at the fit is " << relative_std << " (above "
          << options.max_relative_std
          << "); fix it from the datasheet or log longer, with more power switches";
      throw NumericalError(msg.str());
    }
  }
  result.parameters = current;
  result.predicted_case_c = sensitivity.predicted_case_c;
  result.rms_residual_c = std::sqrt(cost / static_cast<double>(log.case_c.size()));
  result.paper_fit_percent = paper_fit_percent(result.predicted_case_c, log.case_c);
  result.nrmse_fit_percent = nrmse_fit_percent(result.predicted_case_c, log.case_c);
  return result;
}

// Eq. 26.
double paper_fit_percent(const Eigen::Ref<const Eigen::VectorXd>& predicted,
                         const Eigen::Ref<const Eigen::VectorXd>& measured) {
  require_comparable(predicted, measured);
  const double energy = measured.squaredNorm();
  if (!(energy > 0.0)) {
    throw NumericalError("the fit of Eq. 26 is undefined: every measured temperature is zero");
  }
  return 100.0 * (1.0 - (predicted - measured).squaredNorm() / energy);
}

// The normalized root-mean-square-error fit (as MATLAB's compare).
double nrmse_fit_percent(const Eigen::Ref<const Eigen::VectorXd>& predicted,
                         const Eigen::Ref<const Eigen::VectorXd>& measured) {
  require_comparable(predicted, measured);
  const double spread = (measured.array() - measured.mean()).matrix().norm();
  if (!(spread > 0.0)) {
    throw NumericalError("the NRMSE fit is undefined: the measured temperatures are constant");
  }
  return 100.0 * (1.0 - (measured - predicted).norm() / spread);
}

}  // namespace tofcomp::core
