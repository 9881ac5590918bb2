// The mixture of Eq. 8 (the noise w_k) with the noise terms of the grammar
// (core/effect_grammar.hpp). The paper's w_k is drawn from M Gaussian lasing modes with fixed
// offsets, spreads and weights, independently from range to range; the extended mixture relaxes
// each of these and keeps the E and M steps of §5-§6 in closed form:
//   - weights per bin of a covariate: π_{b,i}, b the range's bin of that covariate;
//   - spreads per bin of a covariate (maybe another one): σ²_{b',i};
//   - one mode's offset moving with a covariate: μ_i + β f(c_k), given to the E-step as a per-range
//     shift of each mode's offset (core/model_extension.hpp computes it from its mean terms);
//   - mode persistence: the mode follows a Markov chain with transition matrix A (M × M)
//     instead of independent draws; the E-step is the forward-backward recursion (scaled,
//     O(K·M²)), the M-step counts expected transitions;
//   - outliers: one more component, uniform with density u over the residuals' span, weight ε:
//     p(e) = ε u + (1 − ε) Σ_i π_i N(e; μ_i, σ_i²).
// One more mode is the paper's own model with M + 1 modes (§4 says the M-modal case is
// immediate) and needs nothing here. A range's weight bin and spread bin together are its noise
// state, s = b_w · B_s + b_s; the E-step takes each range's state. Without any extension the
// E-step is exactly the paper's (Eq. 18, Eq. 22): mixture_e_step.
// A Markov chain cannot be combined with binned weights or the outlier component (validate()
// says so): the chain's rows are the weights.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/effect_grammar.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

// A noise parameter per bin of a covariate: the term (its covariate and its B − 1 edges) and
// the B × M table (weights: each row sums to one; variances: positive). For a parametric term
// (linear or decay form, core/effect_grammar.hpp) the table follows from each mode's intercept
// and slope on f at the term's levels (noise_level_values):
//   weights    π_{l,i} ∝ exp(a_i + b_i f_l), mode 1's a and b zero (the log-odds against it);
//   variances  σ²_{l,i} = exp(a_i + b_i f_l);
// refresh_table() computes it. A bins term has no intercept or slope.
struct NoiseBins {
  Term term;
  Eigen::MatrixXd table;
  Eigen::VectorXd intercept;  // a_i (parametric only)
  Eigen::VectorXd slope;      // b_i (parametric only)
  int bins() const { return static_cast<int>(term.knots.size()) + 1; }
  // The table from the intercepts and slopes (parametric terms; a bins term keeps its table).
  void refresh_table();
};

struct ExtendedMixture {
  MixtureParameters modes;  // μ_i, σ_i², π_i (under a Markov chain, π is its initial law)
  std::optional<NoiseBins> weight_bins;
  std::optional<NoiseBins> variance_bins;
  Eigen::MatrixXd transition;    // M × M, each row sums to one; empty: independent draws
  double outlier_weight = 0.0;   // ε in [0, 1); 0: no outlier component
  double outlier_density = 0.0;  // u (1/mm), positive when ε > 0

  int weight_states() const { return weight_bins ? weight_bins->bins() : 1; }
  int variance_states() const { return variance_bins ? variance_bins->bins() : 1; }
  // The number of noise states B_w · B_s (1 without bins).
  int states() const { return weight_states() * variance_states(); }
  int state(int weight_bin, int variance_bin) const {
    return weight_bin * variance_states() + variance_bin;
  }
  bool has_extension() const {
    return weight_bins || variance_bins || transition.size() > 0 || outlier_weight > 0.0;
  }
  // The parameters of mode i in noise state s.
  double weight(int state, int mode) const;
  double variance(int state, int mode) const;
  // Throws InvalidInput naming the first inconsistency.
  void validate() const;
};

// The plain mixture as an extended one without extensions.
ExtendedMixture without_extensions(const MixtureParameters& modes);

struct ExtendedResponsibilities {
  Eigen::MatrixXd mode;         // K × M: P(range k from mode i | all ranges)
  Eigen::VectorXd outlier;      // K: P(range k an outlier | ...) (zeros without the component)
  Eigen::MatrixXd transitions;  // M × M: Σ_k P(mode_{k−1} = i, mode_k = j | ...) (chain only)
};

// E-step on residuals e_k (y_k − d − H_k θ − the bias terms) with each range's noise state and,
// when a mode's offset moves, each range's shift of each mode's offset (K × M; empty: none).
// Returns the log-likelihood log p(e_1..e_K). Computed in log space with per-range scaling: no
// underflow, no NaN. Throws InvalidInput on mismatched lengths or a state out of range.
double extended_e_step(const Eigen::Ref<const Eigen::VectorXd>& residual,
                       const Eigen::Ref<const Eigen::VectorXi>& state,
                       const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                       const ExtendedMixture& model, ExtendedResponsibilities& out);

// log p(e_k) of each range under the extended mixture with independent draws, or under a chain
// the one-step predictive log p(e_k | e_1..e_{k−1}) (their sum is the log-likelihood). With
// resolution h > 0 each Gaussian's density is replaced by the probability of the rounded value
// (core::rounded_mixture_log_probabilities) and the outlier density by u·h: the held-out score.
Eigen::VectorXd extended_log_scores(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                    const Eigen::Ref<const Eigen::VectorXi>& state,
                                    const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                                    const ExtendedMixture& model, double resolution);

// The number of free parameters the extensions add to the paper's mixture (for BIC).
int extension_parameters(const ExtendedMixture& model);

}  // namespace tofcomp::core
