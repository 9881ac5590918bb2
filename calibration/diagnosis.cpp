#include "calibration/diagnosis.hpp"

#include "calibration/compensation.hpp"
#include "core/model_extension.hpp"

namespace tofcomp::calibration {

core::Diagnosis diagnose(const MeasuredData& data, const core::Calibration& calibration) {
  data.require_true_ranges();
  const Compensation compensation = compensate(data, calibration);
  core::DiagnosisInput input;
  input.time_s = data.range_time_s;
  input.junction_c = compensation.junction.junction_c;
  input.junction_rate_c_per_s = core::local_rate(
      data.range_time_s, compensation.junction.junction_c, core::kHeatingRateHalfWindowS);
  input.time_since_power_on_s = data.time_since_power_on();
  input.residual = data.range_mm - data.true_range_mm - compensation.bias_mm;
  return core::diagnose_residuals(input, core::compensation_mixture(calibration).modes);
}

}  // namespace tofcomp::calibration
