// §7 made from the data: the structural choices the paper leaves to the designer (the basis
// family and order of H(.), §4 Examples 1 and 2, and the number of lasing modes M of Eq. 8),
// chosen by the likelihood of held-out ranges, with Algorithm 2's GLR and BIC beside each
// candidate as evidence.
//
// Held out how. The training ranges are cut into blocks of `block` consecutive ranges, and block
// b goes to fold b mod `folds`. A candidate (basis, M) is trained on all of them (§5), then once
// per fold on the other folds, warm-started from the same fold's fit of the order below where
// the bases nest (from the whole fit otherwise), and scored on the fold left out:
// Σ log p(y_k − d − H(t_k)θ) under its mixture, over the fold's ranges whose junction
// temperature lies inside those its training saw (beyond them compensation does not trust the
// basis: it continues the bias along its tangent, core/measurement_model.hpp). Given the junction
// temperatures the modes are drawn independently (Eq. 8), so held-out blocks interleaved with the
// training ones judge the model where it will be used, inside the trained temperatures: a model
// too stiff for the bias loses there, one that fits noise loses too. (Contiguous folds would
// instead judge mostly the extrapolation to a fold's new temperatures, where every basis is
// poor.) Among the candidates whose held-out log-likelihood is within one standard error (from
// the per-block differences: given the temperatures the blocks' ranges are independent) of the best one's, the one with the fewest parameters is chosen (the
// one-standard-error rule: a difference the folds do not resolve does not buy parameters).
//
// Search. A coordinate search, each step warm-started where the bases nest (Legendre order N + 1
// extends order N; Fourier order N + 1 extends order N):
//   1. with the paper's M = 2, polynomial orders 1, 2, … until `patience` orders in a row fail
//      to beat the best (or max_polynomial_order);
//   2. at that order, M = 1 … max_modes;
//   3. with that M, the polynomial orders again (when M changed), then the Fourier family with
//      f0 = 1 / (2 × the training span), so that one period spans twice the temperatures seen.
// A basis fixed by the user skips 1 and 3 (M alone is searched at it); fixed modes skip 2.
// Cost: one EM fit of the whole training set and `folds` warm fits per candidate visited; the
// folds' fits are independent and run through options.parallel_for.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/basis.hpp"
#include "core/em_train.hpp"
#include "core/parallel_for.hpp"

namespace tofcomp::core {


struct StructureSearchOptions {
  int folds = 5;
  // The ranges' rounding (mm; the LMS 200: 1). Held-out ranges are scored by the probability of
  // their rounded value (core::rounded_mixture_log_probabilities), which a mode locked onto the
  // rounding's lattice cannot inflate; 0: by the density, for unrounded data.
  double resolution = 0.0;
  // Consecutive ranges dealt to one fold; fewer on a record too short to give each fold ten.
  Eigen::Index block = 200;
  int max_polynomial_order = 16;
  int max_fourier_order = 8;
  int max_modes = 4;
  // Orders past the best tried before an ascending scan stops.
  int patience = 3;
  // Fixed by the user: then only the other choice is searched (with both fixed there is nothing
  // to search; the caller trains directly).
  std::optional<Basis> basis;
  std::optional<int> modes;
  // The fits' stopping rule and caps (trace off; tolerances loose enough for scoring).
  EmTrainOptions em = search_em_options();
  static EmTrainOptions search_em_options();
  // Runs a candidate's fold fits; empty: one after the other. Any runner gives the same choice
  // and the same figures bit for bit (the folds' scores are summed in fold order).
  ParallelFor parallel_for;
};

// One candidate's evidence.
struct CandidateEvidence {
  std::string family;  // "polynomial", "fourier", or "given" (the user's basis)
  int order = 0;
  int modes = 0;
  std::string name;    // e.g. "polynomial(6, legendre), 3 modes"
  int parameters = 0;  // p + 3M − 1
  bool ok = false;     // false: a fit failed; `error` says why and no score is set
  std::string error;
  double log_likelihood = 0.0;           // ℓ on the whole training set
  double glr = 0.0;                      // Algorithm 2: 2(ℓ − ℓ_0), ℓ_0 of Eq. 28
  double bic = 0.0;                      // −2ℓ + n log K
  double held_out_log_likelihood = 0.0;  // Σ over the folds, per held-out range
  Eigen::VectorXd block_log_likelihood;  // Σ over each scored block's held-out ranges
};

struct StructureChoice {
  std::vector<CandidateEvidence> candidates;  // in the order visited
  int chosen = -1;            // by the one-standard-error rule on held-out likelihood
  int best_by_held_out = -1;  // the largest held-out likelihood
  int best_by_glr = -1;
  int best_by_bic = -1;
  double null_log_likelihood = 0.0;  // ℓ_0 of Eq. 28
  Eigen::Index held_out_ranges = 0;  // scored, over all folds
  // How far the chosen candidate's held-out log-likelihood falls short of the best one's, per
  // held-out range, and the standard error of that difference from the per-block differences
  // (zero when it is the best).
  double shortfall_per_range = 0.0;
  double shortfall_standard_error = 0.0;
  Basis basis;  // the chosen basis, scaled to the training temperatures
  int modes = 0;
  EmTrainResult fit;  // the chosen candidate's fit on the whole training set
};

// The fewest ranges the search judges candidates on (folds × 20); below it training keeps the
// paper's structure (calibration/training.hpp).
Eigen::Index minimum_ranges_for_search(const StructureSearchOptions& options);

using SearchProgress = std::function<void(const CandidateEvidence&)>;

// The search above on junction temperatures t̂^j and y − d of the training ranges, in time
// order. Throws InvalidInput on mismatched or non-finite arguments, fewer than two folds, or
// too few ranges for the folds; NumericalError when no candidate can be trained.
StructureChoice search_structure(const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c,
                                 const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                 const StructureSearchOptions& options = {},
                                 const SearchProgress& progress = {});

}  // namespace tofcomp::core
