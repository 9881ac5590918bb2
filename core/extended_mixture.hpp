// The mixture of Eq. 8 (the noise w_k) with the extensions the residual diagnosis can point to
// (core/residual_diagnosis.hpp). The paper's w_k is drawn from M Gaussian lasing modes with
// fixed weights, independently from range to range; the extended model relaxes that in four
// ways, each of which keeps the E and M steps of §5-§6 in closed form:
//   - temperature-dependent weights: π_i depends on the junction temperature's bin b(k)
//     (B bins with edges from the training data), π_{b,i};
//   - temperature-dependent spread: σ_i² depends on the bin, σ²_{b,i};
//   - mode persistence: the mode follows a Markov chain with transition matrix A (M × M)
//     instead of independent Bernoulli draws; the E-step is the forward-backward recursion
//     (scaled, O(K·M²)), the M-step counts expected transitions;
//   - outliers: one more component, uniform with density u over the residuals' span, weight ε:
//     p(e) = ε u + (1 − ε) Σ_i π_i N(e; μ_i, σ_i²).
// One more mode is the paper's own model with M + 1 modes (§4 says the M-modal case is
// immediate) and needs nothing here. Without any extension the E-step is exactly the paper's
// (Eq. 18, Eq. 22): mixture_e_step.
// A Markov chain cannot be combined with temperature-dependent weights or the outlier component
// here (validate() says so): the diagnosis names one effect at a time.
#pragma once

#include <Eigen/Core>

#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

struct ExtendedMixture {
  MixtureParameters modes;       // μ_i, σ_i², π_i (under a Markov chain, π is its initial law)
  Eigen::VectorXd bin_edges_c;   // B − 1 increasing interior edges; empty: one bin
  Eigen::MatrixXd bin_weight;    // B × M, each row sums to one; empty: modes.weight in every bin
  Eigen::MatrixXd bin_variance;  // B × M, positive; empty: modes.variance in every bin
  Eigen::MatrixXd transition;    // M × M, each row sums to one; empty: independent draws
  double outlier_weight = 0.0;   // ε in [0, 1); 0: no outlier component
  double outlier_density = 0.0;  // u (1/mm), positive when ε > 0

  int bins() const { return static_cast<int>(bin_edges_c.size()) + 1; }
  bool has_extension() const {
    return bin_weight.size() > 0 || bin_variance.size() > 0 || transition.size() > 0 ||
           outlier_weight > 0.0;
  }
  // The bin of each junction temperature (0..B−1).
  Eigen::VectorXi bin_of(const Eigen::Ref<const Eigen::VectorXd>& junction_c) const;
  // The parameters of mode i in bin b.
  double weight(int bin, int mode) const;
  double variance(int bin, int mode) const;
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

// E-step on residuals e_k (y_k − d − H_k θ) with each range's temperature bin. Returns the
// log-likelihood log p(e_1..e_K). Computed in log space with per-range scaling: no underflow,
// no NaN. Throws InvalidInput on mismatched lengths or a bin out of range.
double extended_e_step(const Eigen::Ref<const Eigen::VectorXd>& residual,
                       const Eigen::Ref<const Eigen::VectorXi>& bin, const ExtendedMixture& model,
                       ExtendedResponsibilities& out);

// The number of free parameters the extensions add to the paper's mixture (for BIC).
int extension_parameters(const ExtendedMixture& model);

}  // namespace tofcomp::core
