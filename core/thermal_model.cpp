#include "core/thermal_model.hpp"

#include <algorithm>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <unsupported/Eigen/MatrixFunctions>

#include "core/error.hpp"
#include "core/step_cache.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

void require_step(double step_s, bool zero_allowed) {
  if (!std::isfinite(step_s) || step_s < 0.0 || (!zero_allowed && step_s == 0.0)) {
    std::ostringstream msg;
    msg << "discretization step " << step_s << " s must be a finite "
        << (zero_allowed ? "non-negative" : "positive") << " number of seconds";
    throw InvalidInput(msg.str());
  }
}

}  // namespace

void ThermalParameters::validate() const {
  require_positive(r1_k_per_w, "thermal parameter r1_k_per_w (R1)");
  require_positive(r2_k_per_w, "thermal parameter r2_k_per_w (R2)");
  require_positive(c1_j_per_k, "thermal parameter c1_j_per_k (C1)");
  require_positive(c2_j_per_k, "thermal parameter c2_j_per_k (C2)");
  require_positive(power_w, "thermal parameter power_w (P)");
}

ThermalParameters lms200_example_parameters() {
  ThermalParameters p;
  p.r1_k_per_w = 0.2;
  p.r2_k_per_w = 0.48;
  p.c1_j_per_k = 60.0;
  p.c2_j_per_k = 3750.0;
  p.power_w = 10.0;
  return p;
}

// Eq. 3.
ContinuousThermalModel continuous_model(const ThermalParameters& parameters) {
  parameters.validate();
  const double r1 = parameters.r1_k_per_w;
  const double r2 = parameters.r2_k_per_w;
  const double c1 = parameters.c1_j_per_k;
  const double c2 = parameters.c2_j_per_k;
  ContinuousThermalModel m;
  m.a << -(1.0 / (r2 * c2) + 1.0 / (r1 * c2)), 1.0 / (r1 * c2),  //
      1.0 / (r1 * c1), -1.0 / (r1 * c1);
  m.b_power << 0.0, parameters.power_w / c1;
  m.b_ambient << 1.0 / (r2 * c2), 0.0;
  return m;
}

// Eq. 6: A = I + T a, B = T b_power (B·P of the paper), B′ = T b_ambient.
DiscreteThermalModel discretize_euler(const ThermalParameters& parameters, double step_s) {
  require_step(step_s, false);
  const ContinuousThermalModel c = continuous_model(parameters);
  DiscreteThermalModel d;
  d.a = Eigen::Matrix2d::Identity() + step_s * c.a;
  d.b_power = step_s * c.b_power;
  d.b_ambient = step_s * c.b_ambient;
  d.step_s = step_s;
  const double spectral_radius =
      Eigen::EigenSolver<Eigen::Matrix2d>(d.a, false).eigenvalues().cwiseAbs().maxCoeff();
  if (!(spectral_radius < 1.0)) {
    std::ostringstream msg;
    msg << "forward Euler (Eq. 6) with step " << step_s
        << " s is unstable for these parameters (spectral radius of A " << spectral_radius
        << "); use a shorter step or the exact zero-order hold";
    throw InvalidInput(msg.str());
  }
  return d;
}

// Exact zero-order hold: exp([[a, B], [0, 0]] T) = [[Φ, ∫_0^T e^{as} ds B], [0, I]].
DiscreteThermalModel discretize_zoh(const ThermalParameters& parameters, double step_s) {
  require_step(step_s, true);
  const ContinuousThermalModel c = continuous_model(parameters);
  Eigen::Matrix4d augmented = Eigen::Matrix4d::Zero();
  augmented.topLeftCorner<2, 2>() = c.a;
  augmented.col(2).head<2>() = c.b_power;
  augmented.col(3).head<2>() = c.b_ambient;
  const Eigen::Matrix4d exponential = (augmented * step_s).exp();
  DiscreteThermalModel d;
  d.a = exponential.topLeftCorner<2, 2>();
  d.b_power = exponential.col(2).head<2>();
  d.b_ambient = exponential.col(3).head<2>();
  d.step_s = step_s;
  return d;
}

// Eq. 3, second line.
double junction_rate_c_per_s(const ThermalParameters& parameters, double case_c, double junction_c,
                             double power_on_fraction) {
  return power_on_fraction * parameters.power_w / parameters.c1_j_per_k +
         (case_c - junction_c) / (parameters.r1_k_per_w * parameters.c1_j_per_k);
}

// Eq. 3 with ẋ = 0.
Eigen::Vector2d equilibrium_state(const ThermalParameters& parameters, double power_on_fraction,
                                  double ambient_c) {
  parameters.validate();
  require_on_fraction(power_on_fraction, "power on fraction");
  require_finite(ambient_c, "ambient temperature");
  const double heat = power_on_fraction * parameters.power_w;
  const double case_c = ambient_c + heat * parameters.r2_k_per_w;
  return {case_c, case_c + heat * parameters.r1_k_per_w};
}

// Second line of Eq. 3 with ṫ^j = 0 at a given t^c.
Eigen::Vector2d state_at_case_temperature(const ThermalParameters& parameters, double case_c,
                                          double power_on_fraction) {
  parameters.validate();
  require_on_fraction(power_on_fraction, "power on fraction");
  require_finite(case_c, "case temperature");
  return {case_c, case_c + power_on_fraction * parameters.power_w * parameters.r1_k_per_w};
}

Eigen::Vector2d state_from_case_heat_flow(const ThermalParameters& parameters, double case_c,
                                          double ambient_c) {
  parameters.validate();
  require_finite(case_c, "case temperature");
  require_finite(ambient_c, "ambient temperature");
  const double heat_w =
      std::clamp((case_c - ambient_c) / parameters.r2_k_per_w, 0.0, parameters.power_w);
  return {case_c, case_c + heat_w * parameters.r1_k_per_w};
}

// Eq. 5 without noise.
ThermalTrajectory simulate(const DiscreteThermalModel& model, const Eigen::Vector2d& initial_state,
                           const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
                           const Eigen::Ref<const Eigen::VectorXd>& ambient_c) {
  require_thermal_inputs(power_on_fraction, ambient_c);
  require_finite(initial_state, "initial state");
  require_finite(model.a, "model matrix a");
  require_finite(model.b_power, "model input b_power");
  require_finite(model.b_ambient, "model input b_ambient");
  const Eigen::Index k = power_on_fraction.size();
  ThermalTrajectory out{Eigen::VectorXd(k), Eigen::VectorXd(k)};
  Eigen::Vector2d x = initial_state;
  for (Eigen::Index i = 0; i < k; ++i) {
    out.case_c[i] = x[0];
    out.junction_c[i] = x[1];
    x = model.a * x + model.b_power * power_on_fraction[i] + model.b_ambient * ambient_c[i];
  }
  return out;
}

// Eq. 5 without noise, one exact zero-order hold per interval (reused while the step repeats).
ThermalTrajectory simulate_at_times(const ThermalParameters& parameters,
                                    const Eigen::Vector2d& initial_state,
                                    const Eigen::Ref<const Eigen::VectorXd>& times_s,
                                    const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
                                    const Eigen::Ref<const Eigen::VectorXd>& ambient_c) {
  require_thermal_inputs(power_on_fraction, ambient_c);
  require_same_length(times_s.size(), "sample times", power_on_fraction.size(),
                      "power on fractions");
  require_sample_times(times_s);
  require_finite(initial_state, "initial state");
  const Eigen::Index k = times_s.size();
  ThermalTrajectory out{Eigen::VectorXd(k), Eigen::VectorXd(k)};
  StepCache<DiscreteThermalModel> steps;
  Eigen::Vector2d x = initial_state;
  for (Eigen::Index i = 0; i < k; ++i) {
    out.case_c[i] = x[0];
    out.junction_c[i] = x[1];
    if (i + 1 == k) break;
    const DiscreteThermalModel& model = steps.at(
        times_s[i + 1] - times_s[i], [&](double step_s) { return discretize_zoh(parameters, step_s); });
    x = model.a * x + model.b_power * power_on_fraction[i] + model.b_ambient * ambient_c[i];
  }
  return out;
}

void require_thermal_inputs(const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
                            const Eigen::Ref<const Eigen::VectorXd>& ambient_c) {
  require_same_length(power_on_fraction.size(), "power on fractions", ambient_c.size(),
                      "ambient temperatures");
  if (power_on_fraction.size() == 0)
    throw InvalidInput("a thermal record needs at least one sample");
  require_finite(ambient_c, "ambient temperatures");
  for (Eigen::Index i = 0; i < power_on_fraction.size(); ++i) {
    if (!(power_on_fraction[i] >= 0.0 && power_on_fraction[i] <= 1.0)) {
      std::ostringstream name;
      name << "power on fraction [" << i << "]";
      require_on_fraction(power_on_fraction[i], name.str());
    }
  }
}

void require_sample_times(const Eigen::Ref<const Eigen::VectorXd>& times_s) {
  require_finite(times_s, "sample times");
  for (Eigen::Index i = 1; i < times_s.size(); ++i) {
    if (times_s[i] < times_s[i - 1]) {
      std::ostringstream msg;
      msg << "sample times[" << i << "] = " << times_s[i] << " s is before times[" << i - 1
          << "] = " << times_s[i - 1] << " s: times must be non-decreasing";
      throw InvalidInput(msg.str());
    }
  }
}

void require_on_fraction(double power_on_fraction, std::string_view name) {
  if (!(power_on_fraction >= 0.0 && power_on_fraction <= 1.0)) {
    std::ostringstream msg;
    msg << name << " is " << power_on_fraction << ": it must be in [0, 1]";
    throw InvalidInput(msg.str());
  }
}

}  // namespace tofcomp::core
