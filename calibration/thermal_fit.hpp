// §3.2 on measured data: Algorithm 1 from the datasheet, then the prediction-error fit of the
// thermal network (Eq. 3-6) to the case log, and its fit on held-out data (Eq. 26, NRMSE).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "calibration/measured_data.hpp"
#include "core/thermal_identification.hpp"
#include "core/thermal_map_fit.hpp"

namespace tofcomp::calibration {

// How the thermal network is fitted to the case log (§3.2). Both start from Algorithm 1.
enum class ThermalFitMethod {
  // Every parameter free, the datasheet as a prior (core/thermal_map_fit.hpp): never refuses a
  // log, reports what it held at the datasheet and why. The default.
  DatasheetPrior,
  // The paper's prediction-error method on the parameters `free` names, the others fixed; refuses
  // a log that does not determine them (core/thermal_identification.hpp).
  PredictionError,
};

struct ThermalFitSettings {
  core::DatasheetThermalData datasheet;  // Algorithm 1: the start of the fit
  ThermalFitMethod method = ThermalFitMethod::DatasheetPrior;
  core::MapFitOptions prior;         // DatasheetPrior
  core::ThermalParameterMask free;   // PredictionError: what it fits
  double ambient_fallback_c = 22.0;  // when the data carry no ambient_c
};

struct ThermalFit {
  core::ThermalParameters algorithm1;
  std::optional<core::MapFitResult> map;  // DatasheetPrior's result
  std::optional<core::PemResult> pem;     // PredictionError's result, when map is absent
  // What either method identified, and its fit on the training part.
  const core::ThermalFitResult& training() const;
  const core::ThermalParameters& identified() const { return training().parameters; }
  bool has_held_out = false;
  double held_out_paper_fit_percent = 0.0;  // Eq. 26 on the held-out part
  double held_out_nrmse_fit_percent = 0.0;
  Eigen::VectorXd held_out_time_s, held_out_measured_c, held_out_predicted_c;
};

// Algorithm 1, then the fit of settings.method on `train`, then the fit of the identified model
// driven by the held-out part's inputs (§8.1), when held_out has temperature readings.
ThermalFit fit_thermal(const MeasuredData& train, const MeasuredData* held_out,
                       const ThermalFitSettings& settings);

}  // namespace tofcomp::calibration
