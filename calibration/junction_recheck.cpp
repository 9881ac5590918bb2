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

std::optional<JunctionSource> junction_alternative(const Training& training) {
  const std::optional<JunctionDynamicsFit>& fit = training.junction_dynamics;
  if (!fit) return std::nullopt;
  if (fit->replaced) return JunctionSource::CaseLog;
  if (fit->ranges_answer_above_start()) return JunctionSource::Ranges;
  return std::nullopt;
}

TrainSettings with_rechecked_junction(const TrainSettings& settings,
                                      const std::optional<JunctionRecheck>& recheck) {
  TrainSettings out = settings;
  if (!recheck || !recheck->error.empty()) return out;
  if (recheck->case_log_chosen) {
    out.junction_source = JunctionSource::CaseLog;
  } else if (!recheck->first_from_ranges) {
    out.junction_source = JunctionSource::Ranges;
  }
  return out;
}

TrainedSearch recheck_junction(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options, TrainedSearch trained,
                               const TrainingProgress& progress) {
  const std::optional<JunctionSource> alternative = junction_alternative(trained.training);
  if (!alternative || !search_kept_a_term(trained.search)) return trained;
  const JunctionDynamicsFit& fit = *trained.training.junction_dynamics;
  JunctionRecheck recheck;
  recheck.first_from_ranges = *alternative == JunctionSource::CaseLog;
  recheck.from_ranges = fit.best.dynamics;
  recheck.from_case_log = fit.start.dynamics;
  recheck.kept_first() = trained.search.kept;
  TrainSettings other = settings;
  other.junction_source = *alternative;
  try {
    TrainedSearch again = train_and_search(
        data, other, options,
        progress_part(progress, 0.0, 1.0,
                      recheck.first_from_ranges ? "re-checking the junction from the case log's, "
                                                : "re-checking the junction from the ranges', "));
    const CommonScores scores = common_scores(trained.search, again.search);
    recheck.common_ranges = scores.ranges;
    recheck.first_per_range = scores.first;
    recheck.again_per_range = scores.second;
    recheck.kept_again() = again.search.kept;
    // The first start stands on a tie: the re-check only replaces it when the other predicts
    // held-out ranges better.
    const bool again_chosen = scores.second > scores.first;
    recheck.case_log_chosen = recheck.first_from_ranges == again_chosen;
    if (again_chosen) {
      trained.training = std::move(again.training);
      trained.search = std::move(again.search);
      // A structure re-check reported belongs to the start replaced.
      trained.structure_recheck.reset();
    }
  } catch (const core::Error& e) {
    recheck.error = e.what();
  }
  if (progress) progress(1.0, "re-checking the junction: done");
  trained.junction_recheck = std::move(recheck);
  return trained;
}

}  // namespace tofcomp::calibration
