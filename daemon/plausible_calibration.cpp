#include "daemon/plausible_calibration.hpp"

#include "calibration/plausibility.hpp"
#include "core/error.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::daemon {

void require_plausible(const core::Calibration& calibration) {
  const std::vector<std::string> faults = calibration::implausibilities(calibration);
  if (faults.empty()) return;
  std::string message = "not a calibration of a scanner that can exist:";
  for (const std::string& fault : faults) message += " " + fault + ";";
  message.pop_back();
  throw core::Error(message);
}

std::shared_ptr<const core::Calibration> read_plausible_calibration(
    const settings::DaemonConfig& config) {
  auto calibration = settings::read_configured_calibration(config);
  if (!calibration) return calibration;
  try {
    require_plausible(*calibration);
  } catch (const core::Error& e) {
    throw core::Error("calibration.file " + config.calibration.file.string() + ": " + e.what());
  }
  return calibration;
}

}  // namespace tofcomp::daemon
