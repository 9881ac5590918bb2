// What the configuration makes of the compensation pipeline: its settings and its calibration.
// tofcompd and `tofcomp replay` both build their pipeline here, so that a replay of a recording
// with the daemon's configuration computes what the daemon computed.
#pragma once

#include <memory>

#include "daemon/config/daemon_config.hpp"
#include "io/calibration_file.hpp"
#include "realtime/compensation_pipeline.hpp"

namespace tofcomp::daemon {

// compensation.* and the case sensor's staleness rule.
realtime::PipelineSettings pipeline_settings(const config::DaemonConfig& config);

// calibration.file with the overrides of calibration.noise and calibration.ambient_c; nullptr
// when no file is configured. Throws core::Error naming the file.
std::shared_ptr<const io::Calibration> read_configured_calibration(
    const config::DaemonConfig& config);

}  // namespace tofcomp::daemon
