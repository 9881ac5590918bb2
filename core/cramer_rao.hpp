// How well any unbiased estimator can know d from a window of ranges of Eq. 8 (beyond the
// paper, §8.4's yardstick): the Cramér–Rao bound from the Fisher information of one range, with
// the mixture of lasing modes and the bias known and the device's rounding of each range to its
// resolution (the LMS 200 reports whole millimetres).
//
// One range y = d + b + w, w from the mixture, reported as k = round(y / r). With c = d + b,
//   p_k = Σ_i π_i [Φ((k r + r/2 − c − μ_i) / σ_i) − Φ((k r − r/2 − c − μ_i) / σ_i)],
//   ∂p_k/∂d = Σ_i π_i [φ((k r − r/2 − c − μ_i) / σ_i) − φ((k r + r/2 − c − μ_i) / σ_i)] / σ_i,
//   I(c) = Σ_k (∂p_k/∂d)² / p_k.
// I depends on where c falls between two steps; the bias moves it across them from range to
// range, so the information is averaged over that phase. A window of n ranges holds n I, and the
// bound on the variance of d̂ is 1 / (n I). As a mean absolute error (what §8.4 reports), an
// efficient estimator's Gaussian error reaches √(2/π) √(1 / (n I)).
#pragma once

#include <Eigen/Core>

#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

// I averaged over the rounding phase, in 1/mm². `modes` are the continuous modes before the
// rounding: a mixture trained on rounded ranges holds the rounding's variance, which
// core::modes_before_rounding takes out. Throws InvalidInput on an invalid mixture or a
// resolution that is not positive and finite.
double range_fisher_information(const MixtureParameters& modes, double resolution_mm);

// √(2/π) √(1 / (n I)) for windows of n ranges (n ≥ 1), in mm, from I of one range. Throws
// InvalidInput unless n ≥ 1 and I is positive and finite.
double cramer_rao_mae_mm(double range_information, Eigen::Index n);

}  // namespace tofcomp::core
