// The SICK LMS 200's physical scale, from its datasheet: the one place every check of a range, a
// reference distance or a trained parameter against "what this device can do" takes its numbers
// from (the measured-data reader, io/measurement_rules.hpp; a calibration's plausibility,
// calibration/plausibility.hpp).
#pragma once

namespace tofcomp::core::lms200 {

// The largest range any of its modes reports: 8191 (13 distance bits) in cm in the 8 m mode,
// i.e. 81.91 m (80 m nominal); in mm its modes reach 8191, 16383 and 32767 mm.
inline constexpr double kMaxRangeMm = 81910.0;
// A reference distance (true_range_mm) is a target the device can see: more than 0 and at most
// kMaxRangeMm.
inline constexpr double kMinReferenceMm = 0.0;  // exclusive

// Systematic error ±15 mm and statistical error 5 mm (1σ), in mm mode up to 8 m.
inline constexpr double kSystematicErrorMm = 15.0;
inline constexpr double kStatisticalErrorMm = 5.0;

}  // namespace tofcomp::core::lms200
