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

TrainedSearch recheck_training(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options, TrainedSearch trained,
                               const TrainingProgress& progress) {
  trained = recheck_junction(data, settings, options, std::move(trained),
                             progress_part(progress, 0.0, 0.5, ""));
  return recheck_structure(data, settings, options, std::move(trained),
                           progress_part(progress, 0.5, 0.5, ""));
}

}  // namespace tofcomp::calibration
