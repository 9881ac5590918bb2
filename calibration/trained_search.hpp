// What training and the model search ended with, and the re-checks that may replace them
// (calibration/junction_recheck.hpp, calibration/structure_recheck.hpp).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "calibration/junction_dynamics.hpp"
#include "calibration/model_search.hpp"
#include "calibration/training.hpp"
#include "core/effect_grammar.hpp"

namespace tofcomp::calibration {

// The junction re-checked after the search kept a term (calibration/junction_recheck.hpp).
struct JunctionRecheck {
  // Training took the ranges' junction (their test rejected the case log's) and the re-check
  // trained again from the case log's; or (false) training kept the case log's and the re-check
  // trained again from the ranges' answer, untested.
  bool first_from_ranges = true;
  JunctionDynamics from_ranges;    // the ranges' answer (calibration/junction_dynamics.hpp)
  JunctionDynamics from_case_log;  // the case-log fit's
  std::vector<core::Term> kept_from_ranges;  // what the search from the ranges' junction kept
  std::vector<core::Term> kept_from_case_log;
  Eigen::Index common_ranges = 0;  // scored by both searches
  // The final models' held-out log-likelihood per common range: the first start's and the
  // other's.
  double first_per_range = 0.0;
  double again_per_range = 0.0;
  bool case_log_chosen = false;
  std::string error;  // why the other start's training or search failed (the first stands)

  double from_ranges_per_range() const {
    return first_from_ranges ? first_per_range : again_per_range;
  }
  double from_case_log_per_range() const {
    return first_from_ranges ? again_per_range : first_per_range;
  }
  // What the search from the first start kept, and from the other.
  std::vector<core::Term>& kept_first() {
    return first_from_ranges ? kept_from_ranges : kept_from_case_log;
  }
  const std::vector<core::Term>& kept_first() const {
    return first_from_ranges ? kept_from_ranges : kept_from_case_log;
  }
  std::vector<core::Term>& kept_again() {
    return first_from_ranges ? kept_from_case_log : kept_from_ranges;
  }
  const std::vector<core::Term>& kept_again() const {
    return first_from_ranges ? kept_from_case_log : kept_from_ranges;
  }
  // The other start replaced the first.
  bool again_chosen() const { return error.empty() && case_log_chosen == first_from_ranges; }
};

// The structure re-checked after the search kept a term on the bias
// (calibration/structure_recheck.hpp).
struct StructureRecheck {
  std::string first;  // the structure training chose, e.g. "polynomial(6, legendre), 4 modes"
  int first_modes = 0;
  std::vector<core::Term> bias_terms;  // the kept terms whose bias was taken out
  std::string again;  // the structure chosen on the ranges less that bias
  int again_modes = 0;
  std::vector<core::Term> kept_first;  // what the search kept at the first structure
  // The re-check ran where the first search paused, after the step that kept its first term on
  // the bias (search_and_recheck): kept_first is what it had kept by then, and the search went
  // on from there only where the first structure stood.
  bool first_search_paused = false;
  bool searched_again = false;  // `again` differed: training and the search ran at it
  std::vector<core::Term> kept_again;  // what that search kept
  bool chosen = false;  // its training and search replaced the first
  std::string error;    // why choosing, training or searching again failed (the first stands)
};

// Training and its search, as run; replaced by a re-check's when that is chosen.
struct TrainedSearch {
  Training training;
  ModelSearchResult search;
  std::optional<JunctionRecheck> junction_recheck;    // when it ran
  std::optional<StructureRecheck> structure_recheck;  // when it ran
};

// The re-checks that may replace a training and its search, in order: the junction's
// (calibration/junction_recheck.hpp), then the structure's (calibration/structure_recheck.hpp),
// each on what the one before left; progress: each half.
TrainedSearch recheck_training(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options, TrainedSearch trained,
                               const TrainingProgress& progress = {});

// The model search from `training` (with `settings`) and the re-checks that may replace both.
// Where the junction's re-check cannot run (training kept the case log's junction), the
// structure's runs as soon as a step keeps a term on the bias, the search paused there: the
// steps after it would search from a structure about to be looked at again, and when the
// structure chosen without that bias replaces the first, they are not run at all. Where the
// first structure stands, the search goes on from the step it paused at (and the structure is
// looked at again at its end only if later steps kept more terms on the bias), and then the
// junction's re-check from the ranges' untested answer, unless a structure chosen again replaced
// the training. Otherwise, the whole search, then recheck_training. progress: the search and the
// re-checks, each half.
TrainedSearch search_and_recheck(const MeasuredData& data, const TrainSettings& settings,
                                 const ModelSearchOptions& options, Training training,
                                 const TrainingProgress& progress = {});

// Training with `settings`, then the model search from its calibration with `options`; progress:
// training the first half, the search the second.
TrainedSearch train_and_search(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options,
                               const TrainingProgress& progress = {});

}  // namespace tofcomp::calibration
