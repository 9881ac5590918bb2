// §6: EM testing — the distance d and the mode posteriors Δ̂ from ranges y, the trained bias
// H θ̂ at each sample's junction temperature and the trained mode statistics (Eq. 21-23).
//
// MStep::Exact (default) maximizes the expected complete-data log-likelihood over d:
//   d = Σ_k Σ_i (r_ki / σ_i²)(y_k − H_k θ̂ − μ_i) / Σ_k Σ_i r_ki / σ_i².
// MStep::PaperAsPrinted is Eq. 23 as printed: d = (1ᵀC⁻¹1)⁻¹ 1ᵀC⁻¹(y − Hθ̂), C = Σ_i σ_i² Σ_i;
// it leaves out the mode offsets μ_i, so its d carries their weighted mean.
// μ_i, σ_i² and π_i stay at their trained values, as the paper prescribes.
// Cost: O(K·M) per iteration; the bias H θ̂ is computed once by the caller.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/em_train.hpp"
#include "core/error.hpp"
#include "core/gaussian_mixture.hpp"
#include "core/squarem.hpp"

namespace tofcomp::core {

struct EmTestOptions {
  MStep m_step = MStep::Exact;
  double distance_tolerance = 1e-9;  // stop when |Δd| < this (data units)
  int max_iterations = 500;
  bool record_trace = false;
  // SQUAREM on the map d → d' (core/squarem.hpp), the same fixed point in fewer E-steps; a trace
  // (the paper's Fig. 14) records the plain iteration, so record_trace runs it plain.
  EmAcceleration acceleration = EmAcceleration::Squarem;
  bool operator==(const EmTestOptions&) const = default;
};

struct EmTestResult {
  double distance = 0.0;
  // Standard deviation of d from the observed information of the mixture likelihood
  // (Louis' formula), falling back to the complete-data information if that is not positive.
  double distance_std = 0.0;
  Eigen::MatrixXd responsibilities;  // K × M, the Δ̂ of Eq. 22
  double log_likelihood = 0.0;
  int iterations = 0;
  bool converged = false;
  std::vector<double> distance_trace;  // d after each iteration (the paper's Fig. 14)
};

// The standard deviation of d from −d²ℓ/dd² of the mixture likelihood (Louis' identity, per
// range): Σ_k [Σ_i r_ki P_ki − Σ_i r_ki e_ki² P_ki² + (Σ_i r_ki e_ki P_ki)²], e_ki = x_k − d − μ_i,
// with P_ki = 1/σ²_ki each range's mode precisions; the complete-data information Σ r P when
// the observed one is not positive. Shared by the paper's EM testing and the extended one.
// With mode_shift (K × M, or empty) mode i of range k sits at μ_i + shift_ki.
double distance_standard_deviation(const Eigen::Ref<const Eigen::VectorXd>& corrected, double d,
                                   const Eigen::MatrixXd& responsibilities,
                                   const Eigen::VectorXd& mean, const Eigen::MatrixXd& precision,
                                   const Eigen::Ref<const Eigen::MatrixXd>& mode_shift =
                                       Eigen::MatrixXd(0, 0));

// The checks every EM test makes of its arguments: y and bias of one length K ≥ 1, finite, and
// options and a warm start that can run. Throws InvalidInput naming the first failure.
void validate_test_arguments(const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& bias,
                             const EmTestOptions& options, std::optional<double> initial_distance);

// The iteration of §6 both noise models share, from d: e_step(d) fills the responsibilities at d
// and returns the log-likelihood, m_step() returns the next d from them (Eq. 22, Eq. 23). Stops
// when |Δd| < options.distance_tolerance (converged, the E-step redone at the final d) or after
// options.max_iterations; fills result's log-likelihood, iterations, convergence and trace, and
// returns the final d. The responsibilities e_step last filled are at the d returned.
//
// Under SQUAREM each cycle takes two M-steps d0 → d1 → d2 and tries the extrapolated
// d0 + 2α r + α² v (r = d1 − d0, v = d2 − 2 d1 + d0), kept when its log-likelihood is not below
// d1's (the monotone safeguard), d2 otherwise. In one dimension, on a map that converges
// linearly (d_n = d* + c ρⁿ, the EM of overlapping modes), S3's α = |r| / |v| lands on d* itself.
template <typename EStep, typename DistanceStep>
double iterate_distance(double d, const EmTestOptions& options, EmTestResult& result,
                        const EStep& e_step, const DistanceStep& m_step) {
  if (options.acceleration == EmAcceleration::Squarem && !options.record_trace) {
    SquaremSteps steps;
    result.log_likelihood = e_step(d);
    // One M-step from the point whose E-step is done: false when it settled (the E-step then
    // redone at the new d).
    const auto advance = [&](double& at) {
      const double next = m_step();
      ++result.iterations;
      const bool settled = std::abs(next - at) < options.distance_tolerance;
      at = next;
      result.log_likelihood = e_step(at);
      if (settled) result.converged = true;
      return !settled;
    };
    while (result.iterations < options.max_iterations) {
      const double d0 = d;
      if (!advance(d)) return d;
      const double d1 = d;
      const double d1_log_likelihood = result.log_likelihood;
      if (result.iterations == options.max_iterations) return d;
      const double d2 = m_step();
      ++result.iterations;
      if (std::abs(d2 - d1) < options.distance_tolerance) {
        d = d2;
        result.log_likelihood = e_step(d);
        result.converged = true;
        return d;
      }
      const Eigen::Matrix<double, 1, 1> r(d1 - d0), v(d2 - 2.0 * d1 + d0);
      const double alpha = steps.step_length(r, v);
      if (alpha > 1.0) {
        const double jump =
            SquaremSteps::extrapolate(Eigen::Matrix<double, 1, 1>(d0), r, v, alpha)[0];
        double jump_log_likelihood = -std::numeric_limits<double>::infinity();
        try {
          jump_log_likelihood = e_step(jump);
        } catch (const NumericalError&) {
          // No finite likelihood at the extrapolated d: refused below.
        }
        if (jump_log_likelihood >= d1_log_likelihood) {
          steps.accepted(alpha);
          d = jump;
          result.log_likelihood = jump_log_likelihood;
          continue;
        }
        steps.refused(alpha);
      } else {
        steps.accepted(alpha);
      }
      d = d2;
      result.log_likelihood = e_step(d);
    }
    return d;
  }
  for (;;) {
    result.log_likelihood = e_step(d);
    if (result.iterations == options.max_iterations) return d;
    const double next = m_step();
    ++result.iterations;
    if (options.record_trace) result.distance_trace.push_back(next);
    const bool settled = std::abs(next - d) < options.distance_tolerance;
    d = next;
    if (settled) {
      result.converged = true;
      result.log_likelihood = e_step(d);
      return d;
    }
  }
}

// y and bias (H θ̂) of one length K ≥ 1. Starts from initial_distance when given (a warm start
// from the previous window), otherwise from the paper's d = 1ᵀy / K for PaperAsPrinted and from
// mean(y − H θ̂) − Σ π_i μ_i for Exact.
EmTestResult test_em(const Eigen::Ref<const Eigen::VectorXd>& y,
                     const Eigen::Ref<const Eigen::VectorXd>& bias,
                     const MixtureParameters& mixture, const EmTestOptions& options = {},
                     std::optional<double> initial_distance = std::nullopt);

}  // namespace tofcomp::core
