#include "settings/pipeline_setup.hpp"

namespace tofcomp::settings {

realtime::PipelineSettings pipeline_settings(const DaemonConfig& config) {
  realtime::PipelineSettings s;
  s.window = config.compensation.window;
  s.junction.stale_after_s = config.case_sensor.sensor.limits.max_age.count();
  return s;
}

std::shared_ptr<const core::Calibration> read_configured_calibration(const DaemonConfig& config) {
  if (config.calibration.file.empty()) return nullptr;
  core::Calibration calibration = io::read_calibration_file(config.calibration.file.string());
  calibration.kalman_noise = config.calibration.kalman_noise.applied_to(calibration.kalman_noise);
  if (config.calibration.ambient_c) calibration.ambient_c = *config.calibration.ambient_c;
  return std::make_shared<const core::Calibration>(std::move(calibration));
}

}  // namespace tofcomp::settings
