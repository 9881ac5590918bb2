// Training for a calibration that is to replace a running one (tofcompd's recalibration): on the
// first part of the record (whole power cycles, split as §8 and `tofcomp evaluate` split it), the
// rest held out and scored under both calibrations by the error of §6's window estimate d̂
// against the known distance. Without a running calibration, or when the record cannot spare a
// held-out part (too short, or its first part alone does not train), training takes the whole
// record and there is no comparison; the note says which.
//
// Closing the loop: given search options, the model search of model_search.hpp runs on the part
// trained on (it holds out ranges of its own), and the terms it keeps join the calibration, so
// the held-out comparison judges the extended model. A search that cannot run (too few ranges
// for its folds, a fold that does not fit) leaves the paper's model; the note says why.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "calibration/model_search.hpp"
#include "calibration/plausibility.hpp"
#include "calibration/training.hpp"
#include "core/calibration.hpp"
#include "core/estimators.hpp"

namespace tofcomp::calibration {

// The share of the record's time trained on when a part is held out.
inline constexpr double kHeldOutTrainFraction = 0.7;
// The window of d̂ scored on the held-out part, and the step between windows.
inline constexpr Eigen::Index kHeldOutWindow = 200;
inline constexpr Eigen::Index kHeldOutStride = kHeldOutWindow / 4;
// The fewest held-out ranges a comparison is made on.
inline constexpr Eigen::Index kMinHeldOutRanges = 2 * kHeldOutWindow;

struct HeldOutTraining {
  Training training;
  std::optional<HeldOutComparison> comparison;
  std::string note;  // what was held out, or why nothing was; what the search kept
  std::vector<std::string> kept_terms;  // the search's kept terms by effect name, in order
};

// Throws core::Error when training fails on the whole record.
// `search`: run the model search with these options on the part trained on; null: the paper's
// model only.
HeldOutTraining train_with_held_out(const MeasuredData& data, const TrainSettings& settings,
                                    const core::Calibration* running,
                                    const ModelSearchOptions* search = nullptr);

// d̂'s mean absolute error on windows of kHeldOutWindow ranges of data under calibration.
core::ErrorMoments held_out_error(const MeasuredData& data, const core::Calibration& calibration);

}  // namespace tofcomp::calibration
