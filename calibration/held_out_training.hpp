// Training for a calibration that is to replace a running one (tofcompd's recalibration): on the
// first part of the record (whole power cycles, split as §8 and `tofcomp evaluate` split it), the
// rest held out and scored under both calibrations by the error of §6's window estimate d̂
// against the known distance. Without a running calibration, or when the record cannot spare a
// held-out part (too short, or its first part alone does not train), training takes the whole
// record and there is no comparison; the note says which.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "calibration/measured_data.hpp"
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
  std::string note;  // what was held out, or why nothing was
};

// Throws core::Error when training fails on the whole record.
HeldOutTraining train_with_held_out(const MeasuredData& data, const TrainSettings& settings,
                                    const core::Calibration* running);

// d̂'s mean absolute error on windows of kHeldOutWindow ranges of data under calibration.
core::ErrorMoments held_out_error(const MeasuredData& data, const core::Calibration& calibration);

}  // namespace tofcomp::calibration
