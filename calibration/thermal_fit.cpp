#include "calibration/thermal_fit.hpp"

namespace tofcomp::calibration {
const core::ThermalFitResult& ThermalFit::training() const {
  if (map) return *map;
  return pem.value();
}

ThermalFit fit_thermal(const MeasuredData& train, const MeasuredData* held_out,
                       const ThermalFitSettings& settings) {
  ThermalFit fit;
  fit.algorithm1 = core::identify_from_datasheet(settings.datasheet);
  const core::CaseTemperatureLog training_log = case_log(train, settings.ambient_fallback_c);
  if (settings.method == ThermalFitMethod::DatasheetPrior) {
    fit.map = core::identify_with_datasheet_prior(training_log, fit.algorithm1, settings.prior);
  } else {
    core::PemOptions options;
    options.free = settings.free;
    fit.pem = core::identify_by_prediction_error(training_log, fit.algorithm1, options);
  }
  if (held_out != nullptr && held_out->temperature_time_s.size() >= 2) {
    const core::CaseTemperatureLog log = case_log(*held_out, settings.ambient_fallback_c);
    fit.has_held_out = true;
    fit.held_out_time_s = log.times_s;
    fit.held_out_measured_c = log.case_c;
    fit.held_out_predicted_c = core::predict_case_temperature(log, fit.identified());
    fit.held_out_paper_fit_percent =
        core::paper_fit_percent(fit.held_out_predicted_c, fit.held_out_measured_c);
    fit.held_out_nrmse_fit_percent =
        core::nrmse_fit_percent(fit.held_out_predicted_c, fit.held_out_measured_c);
  }
  return fit;
}

}  // namespace tofcomp::calibration
