// `tofcompd --check-config`: the configuration read and checked as at start, and then every file
// it names opened and loaded as the daemon would load it (docs/daemon.md): the calibration (as
// the compensation path takes it, its extension included), the emulator's scenario and recording,
// the recalibration's datasheet, recording and recordings directory. A missing or broken file
// fails the check, naming the key and the file, so that a configuration the check calls valid
// does not fail at start for a file. (Hardware — serial ports, sensors, GPIO lines — is not
// opened.)
#pragma once

#include <string>

#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

// "valid; calibration C.yaml with the outliers extension; scenario S.yaml; ...": what was
// loaded. Throws core::Error starting with config.source and the key at fault.
std::string check_configuration(const settings::DaemonConfig& config);

}  // namespace tofcomp::daemon
