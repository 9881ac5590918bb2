// EM training (§5) and testing (§6) of Eq. 8 with the extended mixture of
// core/extended_mixture.hpp. Both keep the paper's closed forms:
//   E-step  the responsibilities of the extended mixture (forward-backward under a chain);
//   M-step  (θ, μ) jointly by weighted least squares with weights r_ki / σ²_{b(k),i}
//           (core/mode_regression.hpp, as the paper's exact step), then per bin (or per mode)
//           σ², π in closed form, the transition matrix from the expected transition counts,
//           the outlier weight as the mean outlier responsibility (its density stays fixed);
//   testing d = Σ_k Σ_i w_ki (x_k − μ_i) / Σ_k Σ_i w_ki, x_k = y_k − H_k θ̂, w_ki = r_ki/σ²_ki.
// Each step maximizes the expected complete-data log-likelihood over its block (an ECM), so the
// observed log-likelihood never decreases. Which extensions are fitted is read from the start
// model: a present block is re-estimated, an absent one stays absent.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/em_test.hpp"
#include "core/extended_mixture.hpp"

namespace tofcomp::core {

struct ExtendedEmOptions {
  double log_likelihood_tolerance = 1e-9;  // stop when |Δℓ| / K is below this
  int max_iterations = 300;
  double variance_floor = 1e-6;  // σ² never below this (data units²)
};

struct ExtendedEmResult {
  Eigen::VectorXd theta;
  ExtendedMixture model;
  ExtendedResponsibilities responsibilities;
  double log_likelihood = 0.0;
  int iterations = 0;
  bool converged = false;
  std::vector<double> log_likelihood_trace;  // at the parameters entering each E-step
};

// h: K × p design, y_minus_d: K, bin: K temperature bins of `start`. theta_start: p.
// Throws InvalidInput on bad arguments and NumericalError when a mode or bin loses every range.
ExtendedEmResult train_extended_em(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                   const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                   const Eigen::Ref<const Eigen::VectorXi>& bin,
                                   const Eigen::VectorXd& theta_start, const ExtendedMixture& start,
                                   const ExtendedEmOptions& options = {});

// §6 with the extended mixture: d and the mode posteriors of one window. Starts from
// initial_distance, else from mean(y − bias) − Σ π_i μ_i. The standard deviation is Louis'
// observed information (per range; under a chain this ignores the chain's coupling).
EmTestResult test_extended_em(const Eigen::Ref<const Eigen::VectorXd>& y,
                              const Eigen::Ref<const Eigen::VectorXd>& bias,
                              const Eigen::Ref<const Eigen::VectorXi>& bin,
                              const ExtendedMixture& model, const EmTestOptions& options = {},
                              std::optional<double> initial_distance = std::nullopt);

// B − 1 interior edges splitting the values into B groups of (nearly) equal count.
Eigen::VectorXd quantile_edges(const Eigen::Ref<const Eigen::VectorXd>& values, int bins);

}  // namespace tofcomp::core
