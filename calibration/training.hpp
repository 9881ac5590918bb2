// The whole of training (§3 and §5) on measured data with a known distance: thermal fit, smoothed
// junction temperature, EM training of Eq. 8 into a calibration.
#pragma once

#include <string>

#include "calibration/junction_estimate.hpp"
#include "calibration/measured_data.hpp"
#include "calibration/thermal_fit.hpp"
#include "core/calibration.hpp"
#include "core/em_train.hpp"

namespace tofcomp::calibration {

struct TrainSettings {
  ThermalFitSettings thermal;
  core::ThermalNoise kalman_noise;
  std::string basis = "polynomial:4";
  core::EmTrainOptions em;
};

struct Training {
  core::Calibration calibration;
  ThermalFit thermal;
  SmoothedJunction junction;
  core::EmTrainResult em;
};

// The whole of training on data with a known distance; the calibration's provenance names
// the data set. With held_out, the thermal model's fit is also reported on it (§8.1).
// Throws core::Error with the reason when any stage fails.
Training train_calibration(const MeasuredData& data, const TrainSettings& settings,
                           const MeasuredData* held_out = nullptr);

}  // namespace tofcomp::calibration
