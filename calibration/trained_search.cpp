#include "calibration/trained_search.hpp"

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

}  // namespace tofcomp::calibration
