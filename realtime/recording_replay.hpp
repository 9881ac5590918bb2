// The replay of a tofcompd recording (its format: io/recording_format.hpp) through the
// compensation pipeline: the daemon's outputs again, offline.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "io/measurement_table.hpp"
#include "io/recording_format.hpp"
#include "realtime/compensation_pipeline.hpp"

namespace tofcomp::realtime {

// Feeds a recording's events to `pipeline` in file order and hands each compensated scan to
// `on_scan`. Throws io::MeasuredDataFileError-style core::Error naming the source and line for
// a recording without its geometry or with a beam outside it.
void replay_recording(const io::MeasurementTable& table, const std::string& source,
                      CompensationPipeline& pipeline,
                      const std::function<void(const ipc::CompensatedScan&)>& on_scan);

}  // namespace tofcomp::realtime
