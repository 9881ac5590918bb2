// EM training (§5) and testing (§6) of Eq. 8 extended by terms of the grammar
// (core/effect_grammar.hpp, core/model_extension.hpp). Both keep the paper's closed forms:
//   E-step  the responsibilities of the extended mixture (core/extended_mixture.hpp; the
//           forward-backward recursion under a chain), each mode at its shifted offset
//           μ_i + Z_ki β_i and its state's variance;
//   M-step  θ (the basis and the bias terms' columns), every μ_i and every mode's β_i jointly by
//           weighted least squares with weights r_ki / σ²_{s(k),i} (core/mode_regression.hpp,
//           as the paper's exact step), then per bin (or per mode) σ² and π in closed form, the
//           transition matrix from the expected transition counts, the outlier weight as the
//           mean outlier responsibility (its density stays fixed);
//   testing d = Σ_k Σ_i w_ki (x_k − μ_i − s_ki) / Σ_k Σ_i w_ki, x_k = y_k − bias_k,
//           w_ki = r_ki / σ²_ki, s_ki the mode shift.
// Each step maximizes the expected complete-data log-likelihood over its block (an ECM), so the
// observed log-likelihood never decreases. Which extensions are fitted is read from the start:
// a present block is re-estimated, an absent one stays absent.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/em_test.hpp"
#include "core/extended_mixture.hpp"
#include "core/squarem.hpp"

namespace tofcomp::core {

// The design of an extended fit on K ranges.
struct ExtendedDesign {
  Eigen::MatrixXd shared;                     // K × p: H(t̂^j), then the bias terms' columns
  std::vector<Eigen::MatrixXd> mode_columns;  // M blocks of K × q_i (0 × 0: that mode's offset fixed)
  Eigen::VectorXi state;                      // the noise state of each range (K)
};

// A starting point, and what a fit returns.
struct ExtendedParameters {
  Eigen::VectorXd theta;                           // p
  std::vector<Eigen::VectorXd> mode_coefficients;  // M vectors of q_i (β_i)
  ExtendedMixture model;
};

struct ExtendedEmOptions {
  double log_likelihood_tolerance = 1e-9;  // stop when |Δℓ| / K is below this
  int max_iterations = 300;
  double variance_floor = 1e-6;  // σ² never below this (data units²)
  // SQUAREM (core/squarem.hpp) on the ECM map: the same fixed point in fewer iterations; an
  // iteration is one application of the map, and the trace holds the points moved to.
  EmAcceleration acceleration = EmAcceleration::Squarem;
  // The same ECM step on a sweep that reads the design once an iteration: a design without mode
  // columns under a plain mixture (no extension) is the paper's model with the bias terms'
  // columns beside H and runs on the training's sweep (core/em_train.hpp); any other model of
  // independent draws without an outlier component on core/extended_sweep.hpp's. False: the
  // generic iteration for every model (the tests compare them).
  bool fused_sweeps = true;
};

struct ExtendedEmResult {
  ExtendedParameters fit;
  ExtendedResponsibilities responsibilities;
  double log_likelihood = 0.0;
  int iterations = 0;
  bool converged = false;
  std::vector<double> log_likelihood_trace;  // at the parameters entering each E-step
};

// Each mode's offset shift Z_ki β_i (K × M; empty when no mode has columns).
Eigen::MatrixXd mode_shifts(const ExtendedDesign& design,
                            const std::vector<Eigen::VectorXd>& mode_coefficients);
// Whether any mode's offset has columns.
bool has_mode_columns(const ExtendedDesign& design);
// The shifts of the n ranges from `first` into out (n × M), for a design with mode columns.
void mode_shifts_of_rows(const ExtendedDesign& design,
                         const std::vector<Eigen::VectorXd>& mode_coefficients, Eigen::Index first,
                         Eigen::Index n, Eigen::Ref<Eigen::MatrixXd> out);

// Throws InvalidInput on inconsistent arguments and NumericalError when a mode or bin loses
// every range or a normal matrix is singular.
ExtendedEmResult train_extended_em(const ExtendedDesign& design,
                                   const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                   const ExtendedParameters& start,
                                   const ExtendedEmOptions& options = {});

// §6 with the extended model: d and the mode posteriors of one window, each range with its bias
// (H θ̂ and the bias terms), its noise state and its mode shifts (K × M, or empty). Starts from
// initial_distance, else from mean(y − bias) − Σ π_i μ_i. The standard deviation is Louis'
// observed information (per range; under a chain this ignores the chain's coupling).
EmTestResult test_extended_em(const Eigen::Ref<const Eigen::VectorXd>& y,
                              const Eigen::Ref<const Eigen::VectorXd>& bias,
                              const Eigen::Ref<const Eigen::VectorXi>& state,
                              const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                              const ExtendedMixture& model, const EmTestOptions& options = {},
                              std::optional<double> initial_distance = std::nullopt);

}  // namespace tofcomp::core
