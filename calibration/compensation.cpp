#include "calibration/compensation.hpp"

#include "core/em_test.hpp"

namespace tofcomp::calibration {

Compensation compensate(const MeasuredData& data, const core::Calibration& calibration) {
  Compensation out;
  out.junction = junction_at_ranges(data, calibration.thermal, calibration.kalman_noise,
                                    calibration.ambient_c);
  out.bias_mm = calibration.model.bias(out.junction.junction_c);
  if (calibration.extension) {
    const Eigen::VectorXd time_since_power_on_s = data.time_since_power_on();
    out.bias_mm += calibration.extension->covariate_bias(
        {data.range_time_s, out.junction.junction_c, time_since_power_on_s});
  }
  return out;
}

double held_out_log_likelihood(const MeasuredData& data, const core::Calibration& calibration,
                               const Compensation& compensation) {
  data.require_true_ranges();
  const core::ExtendedMixture mixture = core::compensation_mixture(calibration);
  core::ExtendedResponsibilities scratch;
  return core::extended_e_step(data.range_mm - data.true_range_mm - compensation.bias_mm,
                               mixture.bin_of(compensation.junction.junction_c), mixture, scratch);
}

}  // namespace tofcomp::calibration
