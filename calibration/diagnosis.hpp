// The residual diagnosis (core/residual_diagnosis.hpp) of measured data under a calibration.
#pragma once

#include "calibration/measured_data.hpp"
#include "core/calibration.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::calibration {

// The residual diagnosis (core/residual_diagnosis.hpp) of data with a known distance under a
// calibration; the junction's heating rate is its smoothed estimate's slope over ±30 s. The
// trained model's draws are rounded as the ranges are (MeasuredData::range_resolution_mm) and
// run on `threads` (0: one per core; the result does not depend on it).
core::Diagnosis diagnose(const MeasuredData& data, const core::Calibration& calibration,
                         int threads = 1);

}  // namespace tofcomp::calibration
