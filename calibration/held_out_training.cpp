// Training with a held-out part: see held_out_training.hpp.
#include "calibration/held_out_training.hpp"

#include <fmt/format.h>

#include "calibration/compensation.hpp"
#include "calibration/trained_search.hpp"
#include "calibration/window_evaluation.hpp"
#include "core/error.hpp"

namespace tofcomp::calibration {

core::ErrorMoments held_out_error(const MeasuredData& data, const core::Calibration& calibration) {
  const Compensation compensation = compensate(data, calibration);
  const std::vector<WindowEvaluation> evaluation =
      evaluate_windows(data, calibration, compensation, {kHeldOutWindow}, kHeldOutStride);
  return evaluation.front().em;
}

namespace {

// The search of model_search.hpp on the ranges `trained` was trained on; its kept terms replace
// the training's calibration by the extended one. Returns what the note says of it.
std::string extend_by_search(const MeasuredData& trained_on, const TrainSettings& settings,
                             const ModelSearchOptions& options, HeldOutTraining& out) {
  TrainedSearch trained;
  try {
    trained = search_and_recheck(trained_on, settings, options, out.training);
  } catch (const core::Error& e) {
    return fmt::format("the model search did not run ({}); the paper's model is kept", e.what());
  }
  out.training = std::move(trained.training);
  ModelSearchResult search = std::move(trained.search);
  std::string recheck;
  if (trained.junction_recheck && trained.junction_recheck->error.empty()) {
    const JunctionRecheck& j = *trained.junction_recheck;
    if (j.case_log_chosen && j.first_from_ranges) {
      recheck = " (from the case log's junction, re-checked after the search: it predicts "
                "held-out ranges better than the ranges')";
    } else if (!j.case_log_chosen && !j.first_from_ranges) {
      recheck = " (from the ranges' junction, re-checked after the search: it predicts held-out "
                "ranges better than the case log's)";
    }
  }
  if (trained.structure_recheck && trained.structure_recheck->chosen) {
    recheck += " (at " + trained.structure_recheck->again +
               ", the structure chosen again without the kept terms' bias)";
  }
  if (search.kept.empty()) return "the model search kept no term" + recheck;
  std::string names;
  for (const core::Term& term : search.kept) {
    out.kept_terms.push_back(core::effect_name(term.label()));
    names += (names.empty() ? "" : ", ") + out.kept_terms.back();
  }
  // The search refits the kept terms on all of `trained_on`, from the training's model.
  out.training.calibration = std::move(search.calibration);
  return "the model search kept " + names + recheck;
}

}  // namespace

HeldOutTraining train_with_held_out(const MeasuredData& data, const TrainSettings& settings,
                                    const core::Calibration* running,
                                    const ModelSearchOptions* search) {
  HeldOutTraining out;
  const auto searched = [&](const MeasuredData& trained_on) {
    if (search != nullptr) out.note += "; " + extend_by_search(trained_on, settings, *search, out);
  };
  const auto whole = [&](const std::string& why) {
    out.training = train_calibration(data, settings);
    out.note = "trained on all " + std::to_string(data.range_mm.size()) + " ranges; " + why;
    searched(data);
    return out;
  };
  if (running == nullptr) return whole("no running calibration to compare with");
  const double split = split_time(data, kHeldOutTrainFraction);
  const MeasuredData first = data.slice(-1e300, split);
  const MeasuredData rest = data.slice(split, 1e300);
  if (rest.range_mm.size() < kMinHeldOutRanges) {
    return whole(
        fmt::format("too short to hold a part out ({} ranges after t = {:.0f} s, fewer "
                    "than {})",
                    rest.range_mm.size(), split, kMinHeldOutRanges));
  }
  try {
    out.training = train_calibration(first, settings);
  } catch (const core::Error& e) {
    return whole(fmt::format("its first part alone did not train ({})", e.what()));
  }
  out.note = fmt::format("trained on the {} ranges before t = {:.0f} s, {} after held out",
                         first.range_mm.size(), split, rest.range_mm.size());
  searched(first);
  rest.require_true_ranges();
  HeldOutComparison c;
  c.ranges = static_cast<long>(rest.range_mm.size());
  const core::ErrorMoments fresh = held_out_error(rest, out.training.calibration);
  const core::ErrorMoments old = held_out_error(rest, *running);
  c.windows = static_cast<long>(fresh.count);
  c.new_mae_mm = fresh.mean_absolute_error;
  c.running_mae_mm = old.mean_absolute_error;
  out.comparison = c;
  return out;
}

}  // namespace tofcomp::calibration
