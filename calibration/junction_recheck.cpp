// The junction re-checked after the search kept a term: see junction_recheck.hpp.
#include "calibration/junction_recheck.hpp"

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

bool search_kept_a_term(const ModelSearchResult& search) {
  return search.kept.size() > static_cast<std::size_t>(search.carried_from_training);
}

// The final models' mean held-out log-likelihood over the ranges both searches scored.
struct CommonScores {
  Eigen::Index ranges = 0;
  double first = 0.0;
  double second = 0.0;
};
CommonScores common_scores(const ModelSearchResult& a, const ModelSearchResult& b) {
  if (a.scored.size() != b.scored.size()) {
    throw core::InvalidInput("the two searches scored different records");
  }
  CommonScores out;
  for (std::size_t k = 0; k < a.scored.size(); ++k) {
    if (!a.scored[k] || !b.scored[k]) continue;
    const auto i = static_cast<Eigen::Index>(k);
    out.first += a.final_held_out_scores[i];
    out.second += b.final_held_out_scores[i];
    ++out.ranges;
  }
  if (out.ranges == 0) throw core::InvalidInput("the two searches scored no range in common");
  out.first /= static_cast<double>(out.ranges);
  out.second /= static_cast<double>(out.ranges);
  return out;
}

}  // namespace

bool junction_may_be_rechecked(const Training& training) {
  return training.junction_dynamics && training.junction_dynamics->replaced;
}

TrainedSearch recheck_junction(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options, TrainedSearch trained,
                               const TrainingProgress& progress) {
  if (!junction_may_be_rechecked(trained.training) || !search_kept_a_term(trained.search)) {
    return trained;
  }
  const std::optional<JunctionDynamicsFit>& fit = trained.training.junction_dynamics;
  JunctionRecheck recheck;
  recheck.from_ranges = fit->best.dynamics;
  recheck.from_case_log = fit->start.dynamics;
  recheck.kept_from_ranges = trained.search.kept;
  TrainSettings case_log = settings;
  case_log.junction_from_ranges = false;
  try {
    TrainedSearch again = train_and_search(
        data, case_log, options,
        progress_part(progress, 0.0, 1.0, "re-checking the junction from the case log's, "));
    const CommonScores scores = common_scores(trained.search, again.search);
    recheck.kept_from_case_log = again.search.kept;
    recheck.common_ranges = scores.ranges;
    recheck.from_ranges_per_range = scores.first;
    recheck.from_case_log_per_range = scores.second;
    recheck.case_log_chosen = scores.second > scores.first;
    if (recheck.case_log_chosen) {
      trained.training = std::move(again.training);
      trained.search = std::move(again.search);
    }
  } catch (const core::Error& e) {
    recheck.error = e.what();
  }
  if (progress) progress(1.0, "re-checking the junction: done");
  trained.junction_recheck = std::move(recheck);
  return trained;
}

}  // namespace tofcomp::calibration
