// The Gaussian mixture of the lasing modes in Eq. 8 (M modes; the paper writes M = 2), and the
// E-step shared by training (Eq. 18) and testing (Eq. 22).
#pragma once

#include <Eigen/Core>

namespace tofcomp::core {

// Mode i has offset mean[i] (μ_i), variance[i] (σ_i²) and weight[i]; the weights sum to one.
// For M = 2 the paper's π is weight[1] and its Δ_k is the responsibility of mode 2.
struct MixtureParameters {
  Eigen::VectorXd mean;
  Eigen::VectorXd variance;
  Eigen::VectorXd weight;

  int modes() const { return static_cast<int>(mean.size()); }
  // Throws InvalidInput unless the three vectors have one length ≥ 1, the variances are
  // positive, the weights are in [0, 1] and sum to one (to 1e-9), and every entry is finite.
  void validate() const;
  // Σ_i π_i μ_i: the mean noise offset.
  double mean_offset() const { return weight.dot(mean); }
};

// The mixture without mode `mode` (0-based), the other weights renormalized to sum to one.
// Throws InvalidInput when `mode` is out of range, it is the only mode, or the others weigh
// nothing.
MixtureParameters without_mode(const MixtureParameters& mixture, int mode);

// E-step (Eq. 18, Eq. 22) on residuals e_k: the part of y_k the mixture must explain
// (y_k − d − H_k θ). Fills responsibilities (K × M), r_ki = π_i N(e_k − μ_i, σ_i²) / δ_k, and
// returns the log-likelihood Σ_k log δ_k. Computed by log-sum-exp, so a residual far in the
// tails neither underflows every mode to zero nor yields NaN. O(K·M).
double mixture_e_step(const Eigen::Ref<const Eigen::VectorXd>& residual,
                      const MixtureParameters& mixture, Eigen::MatrixXd& responsibilities);

// log δ_k = log Σ_i π_i N(e_k − μ_i, σ_i²) of each residual (K), by log-sum-exp.
Eigen::VectorXd mixture_log_densities(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                      const MixtureParameters& mixture);

// For ranges rounded to a resolution h (the LMS 200 reports whole millimetres): the log of the
// probability of each rounded value, log Σ_i π_i [Φ((e_k + h/2 − μ_i)/σ_i) − Φ((e_k − h/2 − μ_i)/σ_i)],
// the likelihood rounded data really have. Unlike the density, it is bounded: a mode locked
// onto one rounded value gains nothing a true mode would not (the held-out score of
// core/structure_search.hpp). Tails are taken on the side where they are accurate.
Eigen::VectorXd rounded_mixture_log_probabilities(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                                  const MixtureParameters& mixture,
                                                  double resolution);

// log of one mode's probability of each rounded value, log[Φ((e_k + h/2 − μ_k)/σ_k) −
// Φ((e_k − h/2 − μ_k)/σ_k)], and where that is beyond double precision in the tail,
// log(h N(e_k; μ_k, σ_k²)), its limit there; on arrays over the ranges (vectorized erfc and log).
Eigen::ArrayXd rounded_normal_log_probabilities(const Eigen::Ref<const Eigen::ArrayXd>& residual,
                                                const Eigen::Ref<const Eigen::ArrayXd>& mean,
                                                const Eigen::Ref<const Eigen::ArrayXd>& variance,
                                                double resolution);

// Sheppard's correction: modes fitted by EM to values rounded to a resolution h, as if they were
// continuous, hold the rounding's own variance h²/12 besides their spread (a mode of σ 0.85 mm
// fits at σ 0.90 mm on whole millimetres). The continuous modes whose rounded values the fit
// describes have σ_i² − h²/12; a mode at training's floor of h²/12 keeps a tenth of its
// variance. Whatever rounds the modes again (the probability of a rounded value, draws rounded as
// the device rounds, the Cramér–Rao bound of rounded ranges) takes these, or counts the rounding
// twice. h = 0: the modes as they are.
inline constexpr double kSheppardKeptShare = 0.1;
MixtureParameters modes_before_rounding(MixtureParameters fitted, double resolution);

// Σ_k log Σ_i π_i N(e_k − μ_i, σ_i²), without keeping the responsibilities.
double mixture_log_likelihood(const Eigen::Ref<const Eigen::VectorXd>& residual,
                              const MixtureParameters& mixture);

}  // namespace tofcomp::core
