// §5's EM training (Eq. 13-20) where the distance d is not measured: a scanner in the field
// looks at still surfaces whose distances nobody taped. Each still episode e (a beam seeing one
// fixed surface) has its own unknown distance d_e, a nuisance parameter fitted with θ and the
// modes:
//   y_k = d_{e(k)} + H_k θ + μ_i + ε_k,   ε_k ~ N(0, σ_i²) in mode i,
// and ranges of a bench record with a reference (e(k) = kKnownDistance) enter as y_k − d_k, as in
// train_em. The exact M-step of core/em_train.hpp gains one mean per episode: every range
// belongs to one episode, so the episodes' block of the normal equations is diagonal and is
// profiled out (a Schur complement), leaving the (p + M)-square system of θ and μ; never an
// E × E or K × K matrix. Cost per iteration O(K·(p + M)² + E·(p + M)²).
//
// What the data determine: adding c to every μ_i and −c to every d_e changes no prediction. A
// range with a known distance pins c; without one the fit pins the modes' weighted mean offset
// Σ π_i μ_i to `pinned_mean_offset_mm` (a bench calibration's, or 0) and says so
// (distance_determined false): absolute distances then carry the device's own offset.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/em_train.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

// The episode index of a range whose distance is known (its y is y − d).
inline constexpr int kKnownDistance = -1;

struct FieldEmOptions {
  int modes = 2;
  // σ_i² is kept at or above this (and 1e-6 × the residuals' variance), as in EmTrainOptions.
  double variance_floor = 0.0;
  double min_mode_weight = 1e-3;  // a mode emptied below this ends training (EmptiedModeError)
  int max_iterations = 5000;
  double log_likelihood_tolerance = 1e-10;  // stops when |Δℓ| / K is below this
  // θ and the modes to start from (a bench calibration's); absent: from the ranges less their
  // episodes' medians, by train_em's quantile start.
  std::optional<EmStartingPoint> start;
  // Σ π_i μ_i when no range has a known distance.
  double pinned_mean_offset_mm = 0.0;
};

struct FieldEmResult {
  Eigen::VectorXd theta;
  MixtureParameters mixture;         // modes sorted by increasing mean
  Eigen::VectorXd episode_distance;  // d_e, one per episode
  bool distance_determined = false;  // some range had a known distance
  double log_likelihood = 0.0;
  int iterations = 0;
  bool converged = false;
};

// h: K × p (Eq. 17's regressors, no constant column), y: K, episode: K indices in [0, episodes)
// or kKnownDistance. Every episode needs at least one range. Throws InvalidInput on bad
// arguments and NumericalError (EmptiedModeError) when the data do not determine the fit.
FieldEmResult train_field_em(const Eigen::Ref<const Eigen::MatrixXd>& h,
                             const Eigen::Ref<const Eigen::VectorXd>& y,
                             const std::vector<int>& episode, int episodes,
                             const FieldEmOptions& options = {});

}  // namespace tofcomp::core
