// §3.2 on measured data: Algorithm 1 from the datasheet, then the prediction-error fit of the
// thermal network (Eq. 3-6) to the case log, and its fit on held-out data (Eq. 26, NRMSE).
#pragma once

#include <Eigen/Core>

#include "calibration/measured_data.hpp"
#include "core/thermal_identification.hpp"

namespace tofcomp::calibration {

struct ThermalFitSettings {
  core::DatasheetThermalData datasheet;  // Algorithm 1: the start of the fit
  core::ThermalParameterMask free;       // what the prediction-error method fits
  double ambient_fallback_c = 22.0;      // when the data carry no ambient_c
};

struct ThermalFit {
  core::ThermalParameters algorithm1;
  core::PemResult pem;
  bool has_held_out = false;
  double held_out_paper_fit_percent = 0.0;  // Eq. 26 on the held-out part
  double held_out_nrmse_fit_percent = 0.0;
  Eigen::VectorXd held_out_time_s, held_out_measured_c, held_out_predicted_c;
};

// Algorithm 1, then the prediction-error fit on `train`, then the fit of the identified model
// driven by the held-out part's inputs (§8.1), when held_out has temperature readings.
ThermalFit fit_thermal(const MeasuredData& train, const MeasuredData* held_out,
                       const ThermalFitSettings& settings);

}  // namespace tofcomp::calibration
