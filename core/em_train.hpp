// §5: EM training of Eq. 8 — θ, the mode offsets μ_i, variances σ_i² and weights π_i from
// ranges y with a known distance d and junction temperatures t̂^j (Eq. 13-20).
//
// Two M-steps:
//   MStep::Exact (default) — an expectation-conditional-maximization step: (θ, μ_1..μ_M) solved
//     jointly by weighted least squares with per-mode weights r_ki / σ_i², then σ_i² and π_i in
//     closed form. Each step maximizes the expected complete-data log-likelihood over its block,
//     so the observed log-likelihood never decreases (Meng & Rubin, 1993).
//   MStep::PaperAsPrinted — Eq. 19 exactly as printed, for reproduction: C = Σ_i σ_i² Σ_i,
//     θ = (HᵀC⁻¹H)⁻¹HᵀC⁻¹ỹ (with C's diagonal built from variances, not inverse variances,
//     and without the mode offsets), μ_i the weighted mean of ỹ − Hθ, σ_i² its weighted second
//     moment (μ_i not subtracted), π_i the mean responsibility. It is not a maximization step,
//     so its likelihood may decrease; docs/em-m-step.md shows where the two differ.
// Acceleration: SQUAREM (EmTrainOptions::acceleration) extrapolates along two exact steps and
// keeps the extrapolated point only when its likelihood is not lower (core/squarem.hpp).
// Cost per iteration: O(K·p²) time (one weighted Gram matrix) and O(K·p + K·M) memory.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/gaussian_mixture.hpp"
#include "core/parallel_for.hpp"
#include "core/squarem.hpp"

namespace tofcomp::core {

enum class MStep { Exact, PaperAsPrinted };

enum class EmInitialization {
  // θ from an ordinary least-squares fit with a constant; the residual split at its
  // quantiles into M equal groups gives μ_i and σ_i²; π_i = 1/M. Any M.
  Quantiles,
  // Eq. 20: θ = 0, μ = (0.1, −0.1), σ² = (0.1, 0.1), π = 0.5, in the data's units. M = 2 only.
  Paper,
};

// A starting point for EM: θ and the modes of a previous fit (a warm start). θ may have fewer
// entries than H has columns: the missing ones start at zero, so that a fit of a nested basis
// (Legendre order N + 1 after N) starts where the smaller one ended.
struct EmStartingPoint {
  Eigen::VectorXd theta;
  MixtureParameters mixture;
};

// A weight_tolerance no change of a weight reaches: the paper's rule off, the likelihood's alone
// stops EM (for fits whose likelihood is all that is read).
inline constexpr double kWeightRuleOff = 2.0;

// The variance floor's part that scales with the data: σ_i² ≥ this × var(ỹ) (EmTrainOptions,
// FieldEmOptions).
inline constexpr double kRelativeVarianceFloor = 1e-6;

struct EmTrainOptions {
  int modes = 2;
  MStep m_step = MStep::Exact;
  EmInitialization initialization = EmInitialization::Quantiles;
  // The paper's stopping rule: max_i |Δπ_i| < weight_tolerance.
  double weight_tolerance = 1e-5;
  // Also required unless zero: |Δℓ| / K < this (the paper's rule alone can stop while θ moves).
  double log_likelihood_tolerance = 1e-10;
  int max_iterations = 1000;
  // σ_i² is kept at or above max(variance_floor, 1e-6 × var(ỹ)), so that no mode can collapse
  // onto a single quantized range value and make the likelihood unbounded.
  double variance_floor = 0.0;
  // A mode whose weight falls below this ends training with a NumericalError: the data do not
  // show M modes.
  double min_mode_weight = 1e-3;
  bool record_trace = true;
  // SQUAREM (core/squarem.hpp) on the exact step: the same fixed point in far fewer iterations.
  // MStep::PaperAsPrinted always runs plain EM: it is not a maximization step.
  EmAcceleration acceleration = EmAcceleration::Squarem;
  // When set, EM starts here instead of at `initialization`; its mixture must have `modes` modes.
  std::optional<EmStartingPoint> start;
  // The modes ordered by their means at the end, so that a result does not depend on label
  // switching; false keeps the start's order (for a caller that names modes by index).
  bool sort_modes = true;
  // Runs the exact step's sweeps in stripes on the caller's threads (core/mixture_sweep.hpp);
  // empty: on this thread. Any runner gives the same fit bit for bit.
  ParallelFor parallel_for;
};

// One row of the convergence record (the paper's Fig. 13).
struct EmIterationRecord {
  Eigen::VectorXd mean;
  Eigen::VectorXd variance;
  Eigen::VectorXd weight;
  double log_likelihood = 0.0;  // at the parameters entering this iteration's E-step
};

struct EmTrainResult {
  Eigen::VectorXd theta;
  MixtureParameters mixture;         // modes sorted by increasing mean
  Eigen::MatrixXd responsibilities;  // K × M, r_ki at the final parameters (Δ̂ of Eq. 18)
  double log_likelihood = 0.0;       // at the final parameters
  int iterations = 0;             // M-steps (applications of the EM map)
  int likelihood_evaluations = 0;  // E-steps; under SQUAREM also the extrapolated points tried
  bool converged = false;
  // One row per point the iteration moved to (under SQUAREM: the EM points and the extrapolated
  // points kept); the log-likelihood never decreases along it for MStep::Exact.
  std::vector<EmIterationRecord> trace;
};

// Throws InvalidInput, naming `fit`, unless `start` fits H of `columns` columns and `modes` modes
// (θ no longer than the columns, finite; a valid mixture of that many modes). Shared with the
// field's EM (core/field_em.hpp).
void require_valid_start(const EmStartingPoint& start, Eigen::Index columns, int modes,
                         const std::string& fit);

// Throws EmptiedModeError, naming `fit` and the iteration, when a mode of the responsibilities r
// (K × M) holds less than min_weight of the ranges. Shared with the field's EM.
void require_modes_populated(const Eigen::MatrixXd& r, double min_weight, int iteration,
                             const std::string& fit);

// Trains on H (K × p, Eq. 17) and ỹ = y − d (K). Throws InvalidInput on bad arguments (NaN,
// mismatched lengths, too few samples for p columns and M modes, M < 1, Paper initialization
// with M ≠ 2) and NumericalError when the problem has no unique answer (zero variance, a
// singular HᵀC⁻¹H, a mode losing every sample: EmptiedModeError).
EmTrainResult train_em(const Eigen::Ref<const Eigen::MatrixXd>& h,
                       const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                       const EmTrainOptions& options = {});

}  // namespace tofcomp::core
