// What the configuration makes of the compensation pipeline: its settings and its calibration.
// tofcompd and `tofcomp replay` both build their pipeline here, so that a replay of a recording
// with the daemon's configuration computes what the daemon computed.
#pragma once

#include <memory>

#include "io/calibration_file.hpp"
#include "realtime/compensation_pipeline.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::settings {

// compensation.* and the case sensor's staleness rule.
realtime::PipelineSettings pipeline_settings(const DaemonConfig& config);

// calibration.file with the overrides of calibration.noise and calibration.ambient_c; nullptr
// when no file is configured. Throws core::Error naming the file.
std::shared_ptr<const core::Calibration> read_configured_calibration(const DaemonConfig& config);

}  // namespace tofcomp::settings
