// The configured calibration as tofcompd takes it in: read (settings::read_configured_calibration)
// and refused unless it describes a scanner that can exist (calibration::implausibilities: its
// thermal network's time constants and rises, its modes, the range error it predicts over its
// junction temperatures), at start, at reload and by --check-config, as a recalibration's is
// before it is swapped in. A file that passes its own checks can still describe no device: a
// junction capacity of 1e-300 J/K published 26,607 mm for a raw 3,001 mm.
#pragma once

#include <memory>

#include "core/calibration.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

// Throws core::Error naming every fault ("not a calibration of a scanner that can exist: ...").
void require_plausible(const core::Calibration& calibration);

// Null when no calibration is configured. Throws core::Error naming calibration.file and every
// fault.
std::shared_ptr<const core::Calibration> read_plausible_calibration(
    const settings::DaemonConfig& config);

}  // namespace tofcomp::daemon
