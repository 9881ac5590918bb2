// One sweep over the ranges for the extended EM of core/extended_em.hpp under independent draws
// (no Markov chain, no outlier component): the E-step of the extended mixture
// (core/extended_mixture.hpp: each range's noise state picks its weights and spreads, each mode
// at its shifted offset μ_i + Z_ki β_i) fused with the sums of the normal equations its M-step
// solves for θ, μ and β (core/mode_regression.hpp, weights w_ki = r_ki / σ²_{s(k),i}), chunk by
// chunk in cache, as core/mixture_sweep.hpp does for the paper's model. The generic iteration
// makes a dozen passes over K × M arrays an iteration; this one reads the design once. Internal
// to core/extended_em.cpp.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/extended_em.hpp"
#include "core/mode_regression.hpp"

namespace tofcomp::core {

// Ranges per chunk of the fused path's sweeps: a chunk's columns stay in cache between the
// E-step and the sums.
inline constexpr Eigen::Index kExtendedSweepChunk = 512;

// The normal equations' sums of one sweep, X centred on a fixed row (any row gives the same
// solution; one near the t-weighted mean of X keeps them well conditioned).
struct ExtendedStepSums {
  Eigen::RowVectorXd centre;            // p
  Eigen::MatrixXd gram;                 // p × p (full)
  Eigen::VectorXd gram_rhs;             // p
  std::vector<ModeNormalBlock> blocks;  // per mode
  double log_likelihood = 0.0;
  // The t-weighted mean of X: the centre for the next sweep.
  Eigen::RowVectorXd weighted_mean() const;
};

// The E-step at `at` fused with the sums above. Fills responsibilities.mode (K × M) and zeros in
// responsibilities.outlier. The model must have no chain and no outlier component. Throws
// NumericalError when the log-likelihood is not finite.
ExtendedStepSums extended_step_sweep(const ExtendedDesign& design, const Eigen::VectorXd& y,
                                     const ExtendedParameters& at,
                                     const Eigen::RowVectorXd& centre,
                                     ExtendedResponsibilities& responsibilities);

// Whether the sweep can take this model (independent draws, no outlier component).
bool extended_sweep_applies(const ExtendedMixture& model);

}  // namespace tofcomp::core
