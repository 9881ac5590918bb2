#include "core/thermal_map_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

using LogParameters = Eigen::Matrix<double, kThermalParameterCount, 1>;
using Information = Eigen::Matrix<double, kThermalParameterCount, kThermalParameterCount>;

// A sum of squares is floored here before its logarithm: a log the model fits to rounding error
// is still a finite objective.
constexpr double kMinimumMeanSquareC2 = 1e-12;
// ρ is capped below 1 so that K_eff stays positive; at the cap a log counts as ~500 readings
// per 10⁶.
constexpr double kMaximumLag1Correlation = 0.999;
constexpr double kMinimumEffectiveSamples = 2.0;
// Refits with the determined directions found again at the answer, at most this many.
constexpr int kMaximumSubspaceRounds = 3;

const ThermalParameterMask kAllFree{true, true, true, true, true};

ThermalParameters parameters_at(const LogParameters& theta) {
  std::array<double, kThermalParameterCount> v{};
  for (int i = 0; i < kThermalParameterCount; ++i)
    v[static_cast<std::size_t>(i)] = std::exp(theta[i]);
  return thermal_parameters_from(v);
}

// The negative log posterior of the header, or +∞ where the prediction is not finite.
struct Objective {
  const CaseTemperatureLog& log;
  const LogParameters& prior_mean;
  double prior_precision;    // 1 / s²
  double effective_samples;  // K_eff

  double floored(double sum_of_squares) const {
    return std::max(sum_of_squares, kMinimumMeanSquareC2 * static_cast<double>(log.case_c.size()));
  }
  double operator()(const LogParameters& theta, double sum_of_squares) const {
    if (!std::isfinite(sum_of_squares)) return std::numeric_limits<double>::infinity();
    return 0.5 * effective_samples * std::log(floored(sum_of_squares)) +
           0.5 * prior_precision * (theta - prior_mean).squaredNorm();
  }
  double sum_of_squares(const LogParameters& theta) const {
    const double s =
        (predict_case_temperature(log, parameters_at(theta)) - log.case_c).squaredNorm();
    return std::isfinite(s) ? s : std::numeric_limits<double>::infinity();
  }
};

struct FitState {
  LogParameters theta;
  CaseSensitivity sensitivity;
  double sum_of_squares = 0.0;
  int iterations = 0;
  bool converged = false;
};

FitState sensitivity_at(const CaseTemperatureLog& log, const LogParameters& theta) {
  FitState s;
  s.theta = theta;
  s.sensitivity = case_temperature_sensitivity(log, parameters_at(theta), kAllFree);
  s.sum_of_squares = (s.sensitivity.predicted_case_c - log.case_c).squaredNorm();
  return s;
}

// The data's information about θ at a state: Jᵀ J / σ̂², σ̂² = SSR / K_eff.
Information data_information(const FitState& s, const Objective& objective) {
  const double weight = objective.effective_samples / objective.floored(s.sum_of_squares);
  return weight * (s.sensitivity.jacobian.transpose() * s.sensitivity.jacobian);
}

// Levenberg–Marquardt on the objective from `state`, moving θ only within the span of the
// orthonormal columns of `directions`.
FitState minimize(const Objective& objective, FitState state, const Eigen::MatrixXd& directions,
                  const MapFitOptions& options) {
  if (directions.cols() == 0) {
    state.converged = true;
    return state;
  }
  double objective_value = objective(state.theta, state.sum_of_squares);
  double damping = 1e-3;
  for (int iteration = 1; iteration <= options.max_iterations && !state.converged; ++iteration) {
    ++state.iterations;
    const double weight = objective.effective_samples / objective.floored(state.sum_of_squares);
    const Eigen::VectorXd residual = state.sensitivity.predicted_case_c - objective.log.case_c;
    const LogParameters gradient = weight * (state.sensitivity.jacobian.transpose() * residual) +
                                   objective.prior_precision * (state.theta - objective.prior_mean);
    const Information hessian =
        data_information(state, objective) + objective.prior_precision * Information::Identity();
    const Eigen::VectorXd reduced_gradient = directions.transpose() * gradient;
    const Eigen::MatrixXd reduced_hessian = directions.transpose() * hessian * directions;
    bool accepted = false;
    while (!accepted) {
      Eigen::MatrixXd damped = reduced_hessian;
      damped.diagonal() += damping * reduced_hessian.diagonal();
      LogParameters step = directions * (-damped.ldlt().solve(reduced_gradient));
      const double largest = step.cwiseAbs().maxCoeff();
      if (largest > options.max_log_step) step *= options.max_log_step / largest;
      const LogParameters trial = state.theta + step;
      const double trial_ssr = objective.sum_of_squares(trial);
      const double trial_value = objective(trial, trial_ssr);
      if (trial_value < objective_value) {
        accepted = true;
        state.converged = step.cwiseAbs().maxCoeff() < options.step_tolerance ||
                          objective_value - trial_value <=
                              options.relative_cost_tolerance * std::abs(objective_value);
        const int iterations = state.iterations;
        state = sensitivity_at(objective.log, trial);
        state.iterations = iterations;
        objective_value = trial_value;
        damping = std::max(damping / 3.0, 1e-12);
      } else if ((damping *= 4.0) > 1e16) {
        state.converged = true;  // no step lowers the objective: a minimum to working precision
        break;
      }
    }
  }
  return state;
}

// The eigen-directions of the data's information whitened by the prior (S = s² I, so whitening
// scales it by s²), ascending, with their data-over-prior ratios.
Eigen::SelfAdjointEigenSolver<Information> whitened_information(const FitState& state,
                                                                const Objective& objective) {
  return Eigen::SelfAdjointEigenSolver<Information>(data_information(state, objective) /
                                                    objective.prior_precision);
}

// The directions the data determine: those they know at least min_data_over_prior times more
// precisely (in information) than the datasheet does.
Eigen::MatrixXd determined_directions(const FitState& state, const Objective& objective,
                                      const MapFitOptions& options) {
  const auto eigen = whitened_information(state, objective);
  int first = 0;
  while (first < kThermalParameterCount &&
         !(eigen.eigenvalues()[first] >= options.min_data_over_prior)) {
    ++first;
  }
  return eigen.eigenvectors().rightCols(kThermalParameterCount - first);
}

// ρ of the demeaned residual.
double lag1_correlation(const Eigen::VectorXd& residual) {
  const Eigen::ArrayXd r = residual.array() - residual.mean();
  const Eigen::Index n = r.size();
  const double energy = r.square().sum();
  if (n < 2 || !(energy > 0.0)) return 0.0;
  const double lagged = (r.head(n - 1) * r.tail(n - 1)).sum();
  return std::clamp(lagged / energy, 0.0, kMaximumLag1Correlation);
}

}  // namespace

void MapFitOptions::validate() const {
  require_positive(prior_log_std, "prior_log_std");
  if (max_iterations < 1) throw InvalidInput("max_iterations must be at least 1");
  require_positive(max_log_step, "max_log_step");
  if (!(step_tolerance >= 0.0) || !(relative_cost_tolerance >= 0.0)) {
    throw InvalidInput("MAP fit tolerances must be non-negative");
  }
  require_positive(min_data_over_prior, "min_data_over_prior");
  if (!(held_below_data_share >= 0.0 && held_below_data_share <= 1.0)) {
    throw InvalidInput("held_below_data_share must be in [0, 1]");
  }
}

MapFitResult identify_with_datasheet_prior(const CaseTemperatureLog& log,
                                           const ThermalParameters& datasheet,
                                           const MapFitOptions& options) {
  log.validate();
  datasheet.validate();
  options.validate();
  const Eigen::Index k = log.case_c.size();
  if (k < 2) {
    throw InvalidInput("the thermal fit needs at least two case readings (the log has " +
                       std::to_string(k) + ")");
  }
  LogParameters prior_mean;
  const auto values = thermal_parameter_values(datasheet);
  for (int i = 0; i < kThermalParameterCount; ++i) {
    prior_mean[i] = std::log(values[static_cast<std::size_t>(i)]);
  }
  const double prior_variance = options.prior_log_std * options.prior_log_std;

  // First fit counting every reading, in the directions the data determine at the datasheet;
  // then ρ of its residuals fixes K_eff, and the final fit starts again from the datasheet in the
  // directions the data determine at the first fit's answer.
  Objective objective{log, prior_mean, 1.0 / prior_variance, static_cast<double>(k)};
  const FitState at_datasheet = sensitivity_at(log, prior_mean);
  const FitState first = minimize(objective, at_datasheet,
                                  determined_directions(at_datasheet, objective, options), options);
  const double rho = lag1_correlation(first.sensitivity.predicted_case_c - log.case_c);
  objective.effective_samples = std::clamp(static_cast<double>(k) * (1.0 - rho) / (1.0 + rho),
                                           kMinimumEffectiveSamples, static_cast<double>(k));
  // The directions the data determine depend on where they are looked at: refit from the
  // datasheet until the answer determines as many as the fit used (or kMaximumSubspaceRounds).
  Eigen::MatrixXd determined = determined_directions(first, objective, options);
  FitState final_state = minimize(objective, at_datasheet, determined, options);
  int iterations = first.iterations + final_state.iterations;
  for (int round = 1; round < kMaximumSubspaceRounds; ++round) {
    Eigen::MatrixXd again = determined_directions(final_state, objective, options);
    if (again.cols() == determined.cols()) break;
    determined = std::move(again);
    final_state = minimize(objective, at_datasheet, determined, options);
    iterations += final_state.iterations;
  }

  MapFitResult result;
  result.prior = datasheet;
  result.parameters = parameters_at(final_state.theta);
  result.residual_lag1_correlation = rho;
  result.effective_samples = objective.effective_samples;
  result.iterations = iterations;
  result.converged = final_state.converged;

  // The posterior: (data information + prior precision)⁻¹ in the determined directions D, the
  // prior alone in the held ones N (the fit did not let the data move them):
  // C = D (Dᵀ (I_data + I_prior) D)⁻¹ Dᵀ + s² N Nᵀ, 5 × 5.
  const Information data = data_information(final_state, objective);
  const Information projector_determined = determined * determined.transpose();
  const Information projector_held = Information::Identity() - projector_determined;
  Information covariance = prior_variance * projector_held;
  if (determined.cols() > 0) {
    const Eigen::MatrixXd reduced = determined.transpose() *
                                    (data + objective.prior_precision * Information::Identity()) *
                                    determined;
    covariance +=
        determined *
        reduced.ldlt().solve(Eigen::MatrixXd::Identity(determined.cols(), determined.cols())) *
        determined.transpose();
  }
  for (int i = 0; i < kThermalParameterCount; ++i) {
    const auto n = static_cast<std::size_t>(i);
    result.relative_std[n] = std::sqrt(std::max(covariance(i, i), 0.0));
    result.data_share[n] = std::clamp(1.0 - covariance(i, i) / prior_variance, 0.0, 1.0);
    result.held[n] = result.data_share[n] < options.held_below_data_share;
  }
  // The held directions, weakest first, each with its data-over-prior ratio at the answer.
  const Eigen::MatrixXd held_basis = whitened_information(final_state, objective)
                                         .eigenvectors()
                                         .leftCols(kThermalParameterCount - determined.cols());
  for (Eigen::Index c = 0; c < held_basis.cols(); ++c) {
    LogParameters v = projector_held * held_basis.col(c);
    if (!(v.norm() > 0.0)) continue;
    v.normalize();
    Eigen::Index largest = 0;
    v.cwiseAbs().maxCoeff(&largest);
    if (v[largest] < 0.0) v = -v;  // the largest component positive
    PriorHeldDirection d;
    for (int j = 0; j < kThermalParameterCount; ++j)
      d.log_direction[static_cast<std::size_t>(j)] = v[j];
    d.data_over_prior = std::max(v.dot(data * v) / objective.prior_precision, 0.0);
    result.prior_held_directions.push_back(d);
  }
  result.predicted_case_c = final_state.sensitivity.predicted_case_c;
  result.rms_residual_c = std::sqrt(final_state.sum_of_squares / static_cast<double>(k));
  result.paper_fit_percent = paper_fit_percent(result.predicted_case_c, log.case_c);
  result.nrmse_fit_percent = nrmse_fit_percent(result.predicted_case_c, log.case_c);
  return result;
}

}  // namespace tofcomp::core
