#include "calibration/trained_search.hpp"

#include "calibration/junction_recheck.hpp"
#include "calibration/structure_recheck.hpp"

namespace tofcomp::calibration {

TrainedSearch train_and_search(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options,
                               const TrainingProgress& progress) {
  TrainedSearch out;
  out.training =
      train_calibration(data, settings, nullptr, progress_part(progress, 0.0, 0.5, "training: "));
  out.search = search_model(data, out.training.calibration, out.training.junction, options,
                            progress_part(progress, 0.5, 0.5, "the search: "));
  return out;
}

namespace {

bool kept_a_bias_term(const SearchStep& step) {
  return step.kept && step.named()->term.parameter == core::Parameter::Bias;
}

}  // namespace

TrainedSearch search_and_recheck(const MeasuredData& data, const TrainSettings& settings,
                                 const ModelSearchOptions& options, Training training,
                                 const TrainingProgress& progress) {
  const TrainingProgress searching = progress_part(progress, 0.0, 0.5, "the search: ");
  const TrainingProgress rechecking = progress_part(progress, 0.5, 0.5, "");
  ModelSearchRun first(data, training.calibration, training.junction, options, searching);
  const bool early = !junction_may_be_rechecked(training);
  bool looked_again = false;  // the structure's re-check ran, or could not, at a paused step
  std::optional<StructureRecheck> early_recheck;
  while (first.next_step()) {
    if (!early || looked_again || !kept_a_bias_term(first.steps().back())) continue;
    looked_again = true;
    TrainedSearch paused{std::move(training), first.result(), std::nullopt, std::nullopt};
    paused = recheck_structure(data, settings, options, std::move(paused), rechecking);
    if (paused.structure_recheck) paused.structure_recheck->first_search_paused = true;
    if (paused.structure_recheck && paused.structure_recheck->chosen) return paused;
    training = std::move(paused.training);
    early_recheck = std::move(paused.structure_recheck);
  }
  if (searching) searching(1.0, "done");
  TrainedSearch trained{std::move(training), first.result(), std::nullopt, std::nullopt};
  if (!looked_again) {
    return recheck_training(data, settings, options, std::move(trained), rechecking);
  }
  if (early_recheck && kept_bias_terms(trained.search).size() > early_recheck->bias_terms.size()) {
    trained = recheck_structure(data, settings, options, std::move(trained),
                                progress_part(rechecking, 0.0, 0.5, ""));
  } else {
    trained.structure_recheck = std::move(early_recheck);
  }
  // Training kept the case log's junction; the ranges' untested answer is judged as in
  // recheck_training, unless a structure chosen again has replaced that training.
  if (trained.structure_recheck && trained.structure_recheck->chosen) return trained;
  return recheck_junction(data, settings, options, std::move(trained),
                          progress_part(rechecking, 0.5, 0.5, ""));
}

TrainedSearch recheck_training(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options, TrainedSearch trained,
                               const TrainingProgress& progress) {
  trained = recheck_junction(data, settings, options, std::move(trained),
                             progress_part(progress, 0.0, 0.5, ""));
  return recheck_structure(data, settings, options, std::move(trained),
                           progress_part(progress, 0.5, 0.5, ""));
}

}  // namespace tofcomp::calibration
