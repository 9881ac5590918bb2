// Whether a new calibration may replace the running one (docs/daemon.md, "Recalibration"):
// its parameters within the LMS 200's physical scale (core/lms200_limits.hpp), and, where the
// same held-out data could be scored under both, its error there no worse than the running
// calibration's by more than a stated margin. A calibration trained on a reference distance off
// by half a metre, or on one impossible row, fails the first; one trained on too little or on
// data from another set-up, the second.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration.hpp"
#include "core/lms200_limits.hpp"

namespace tofcomp::calibration {

// The range error the calibration predicts, μ_i + H(t)θ, in every mode i at every trained junction
// temperature t, at most this far from 0: over three times the device's systematic error, "a few
// cm". (The offsets and the bias are checked together: where the basis and the offsets share a
// constant, each may be large while their sum, the prediction, is not.)
inline constexpr double kMaxRangeErrorMm = 50.0;
// The modes at most this far apart: a few cm.
inline constexpr double kMaxModeSeparationMm = 50.0;
// A mode's standard deviation σ_i at most this: six times the device's statistical error.
inline constexpr double kMaxModeSpreadMm = 30.0;
// Junction temperatures a laser diode in a working scanner can have.
inline constexpr double kMinJunctionC = -40.0;
inline constexpr double kMaxJunctionC = 150.0;
// The thermal network's time constants R1·C1 (junction over case) and R2·C2 (case over ambient,
// Eq. 2): from a tenth of a second, a junction that follows its power at once, to a day, a case
// that never warms. The LMS 200's are about 12 s and 30 min.
inline constexpr double kMinThermalTimeConstantS = 0.1;
inline constexpr double kMaxThermalTimeConstantS = 86400.0;
// Its steady rises P·R1 and P·R2: positive, and at most the span of the junction temperatures a
// working laser diode can have.
inline constexpr double kMaxThermalRiseK = kMaxJunctionC - kMinJunctionC;
// Points of the trained junction range at which the predicted error is checked.
inline constexpr int kBiasCheckPoints = 101;

// The held-out criterion: the new calibration's mean absolute error of d̂ on the held-out
// windows may exceed the running one's by at most this fraction of it plus this many mm.
inline constexpr double kHeldOutMarginFraction = 0.10;
inline constexpr double kHeldOutMarginMm = 0.05;

// What is physically wrong with a calibration, one sentence each naming the parameter and its
// bound; empty when nothing is.
std::vector<std::string> implausibilities(const core::Calibration& calibration);

// The held-out scores of the new and the running calibration on the same windows.
struct HeldOutComparison {
  long ranges = 0;   // held-out ranges
  long windows = 0;  // held-out windows scored
  double new_mae_mm = 0.0;
  double running_mae_mm = 0.0;
};

// Why the new calibration predicts the held-out data too much worse than the running one, or
// nullopt when it does not.
std::optional<std::string> held_out_regression(const HeldOutComparison& comparison);

}  // namespace tofcomp::calibration
