// The daemon's recordings in the interchange CSV (../shared/docs/data-format.md) and their
// replay through the compensation pipeline. A recording holds the events in the order the
// daemon took them: a case reading is a row with case_temp_c, a power change a row with power,
// a scan one row per beam with an echo (range_mm, beam), all at the scan's time_s. Metadata
// lines give the scan geometry (`beams`, `start_angle_deg`, `resolution_deg`) so that a beam
// with no echo (no row) is known to exist. Times are written in the shortest form that reads
// back exactly, so a replay takes the very numbers the daemon took.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "io/measurement_table.hpp"
#include "realtime/compensation_pipeline.hpp"

namespace tofcomp::realtime {

inline constexpr const char* kRecordingBeamsKey = "beams";
inline constexpr const char* kRecordingStartAngleKey = "start_angle_deg";
inline constexpr const char* kRecordingResolutionKey = "resolution_deg";

// A recording's scan geometry, from its metadata lines.
struct RecordingGeometry {
  std::size_t beams = 0;
  double start_angle_deg = 0.0;
  double resolution_deg = 0.0;
};

// Throws core::InvalidInput naming `source` when a geometry line is missing or not a number, or
// `beams` is not a whole number from 1 to 65535.
RecordingGeometry read_recording_geometry(const io::MeasurementTable& table,
                                          const std::string& source);

// The columns and metadata of a recording of scans of this geometry.
std::vector<std::string> recording_columns();
std::vector<io::MetadataLine> recording_metadata(std::size_t beams, double start_angle_deg,
                                                 double resolution_deg);

// The rows of one scan, appended to `rows`.
void append_scan_rows(const RawScan& scan, std::vector<io::MeasurementRow>& rows);

// Feeds a recording's events to `pipeline` in file order and hands each compensated scan to
// `on_scan`. Throws io::MeasurementFileError-style core::Error naming the source and line for
// a recording without its geometry or with a beam outside it.
void replay_recording(const io::MeasurementTable& table, const std::string& source,
                      CompensationPipeline& pipeline,
                      const std::function<void(const ipc::CompensatedScan&)>& on_scan);

}  // namespace tofcomp::realtime
