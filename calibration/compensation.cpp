#include "calibration/compensation.hpp"

#include <utility>

#include "calibration/covariates.hpp"
#include "core/em_test.hpp"

namespace tofcomp::calibration {

Compensation compensate(const MeasuredData& data, const core::Calibration& calibration) {
  return compensate(data, calibration,
                    junction_at_ranges(data, calibration.thermal, calibration.kalman_noise,
                                       calibration.ambient_c));
}

Compensation compensate(const MeasuredData& data, const core::Calibration& calibration,
                        SmoothedJunction junction) {
  Compensation out;
  out.junction = std::move(junction);
  out.bias_mm = calibration.model.bias(out.junction.junction_c);
  out.noise_state = Eigen::VectorXi::Zero(data.range_mm.size());
  if (calibration.extension) {
    const core::CovariateTable covariates = covariate_table(data, out.junction);
    out.bias_mm += calibration.extension->bias(covariates);
    out.noise_state = calibration.extension->states(covariates);
    out.mode_shift = calibration.extension->mode_shift(covariates);
  }
  return out;
}

double held_out_log_likelihood(const MeasuredData& data, const core::Calibration& calibration,
                               const Compensation& compensation) {
  data.require_true_ranges();
  const core::ExtendedMixture mixture = core::compensation_mixture(calibration);
  core::ExtendedResponsibilities scratch;
  return core::extended_e_step(data.range_mm - data.true_range_mm - compensation.bias_mm,
                               compensation.noise_state, compensation.mode_shift, mixture,
                               scratch);
}

}  // namespace tofcomp::calibration
