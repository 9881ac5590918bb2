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
// `on_scan`: a scan is the range rows of one time_s, one per beam (a beam met again at the same
// time starts the next scan). A tofcompd recording gives its geometry in metadata lines; measured
// data without them replays with the beams its rows name and unknown (NaN) angles
// (io::read_recording_geometry). Throws core::InvalidInput naming the source and line for an
// incomplete geometry or a beam outside it.
void replay_recording(const io::MeasurementTable& table, const std::string& source,
                      CompensationPipeline& pipeline,
                      const std::function<void(const ipc::CompensatedScan&)>& on_scan);
// The same, each compensated scan handed over with the scan it came from (its time, and which
// beams the rows gave: the others are no_echo).
void replay_recording(
    const io::MeasurementTable& table, const std::string& source, CompensationPipeline& pipeline,
    const std::function<void(const RawScan& in, const ipc::CompensatedScan& out)>& on_scan);

}  // namespace tofcomp::realtime
