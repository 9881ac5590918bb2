// tofcompd's recordings: the interchange CSV (../shared/docs/data-format.md) with the events in
// the order the daemon took them. A case reading is a row with case_temp_c, a power change a row
// with power, a scan one row per beam with an echo (range_mm, beam), all at the scan's time_s.
// Metadata lines give the scan geometry (`beams`, `start_angle_deg`, `resolution_deg`) so that a
// beam with no echo (no row) is known to exist. Times are written in the shortest form that reads
// back exactly, so a replay takes the very numbers the daemon took. Written by the daemon's
// recorder, replayed by realtime/recording_replay.hpp and played by the emulated LMS 200.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/measurement_table.hpp"

namespace tofcomp::io {

inline constexpr const char* kRecordingBeamsKey = "beams";
inline constexpr const char* kRecordingStartAngleKey = "start_angle_deg";
inline constexpr const char* kRecordingResolutionKey = "resolution_deg";

// The most beams a recording may declare or a file's beam column may reach.
inline constexpr std::size_t kMaxRecordingBeams = 65535;

// A recording's scan geometry, from its metadata lines.
struct RecordingGeometry {
  std::size_t beams = 0;
  // NaN when the file does not give them: measured data from another logger carries beam
  // indices, not angles, and an angle made up here would be published as if measured.
  double start_angle_deg = 0.0;
  double resolution_deg = 0.0;
};

// The geometry of a tofcompd recording from its three metadata lines. A file without the two
// angle lines is measured data in the interchange CSV (a user's own logger, `tofcomp simulate`):
// its beams are those its rows name (the highest `beam` + 1, beam 0 where the column is absent,
// or its '# beams' line's count when that is more) and its angles unknown (NaN). Throws
// core::InvalidInput naming `source` when one angle line is there without the other or the beam
// count, or a line is not a number, when `beams` is not a whole number from 1 to
// kMaxRecordingBeams, or when a row's beam is beyond that limit.
RecordingGeometry read_recording_geometry(const MeasurementTable& table, const std::string& source);

// The columns and metadata of a recording of scans of this geometry.
std::vector<std::string> recording_columns();
std::vector<MetadataLine> recording_metadata(std::size_t beams, double start_angle_deg,
                                             double resolution_deg);

// The rows of one scan taken at time_s: one per beam with an echo (no_echo[b] == 0).
void append_scan_rows(double time_s, const std::vector<double>& ranges_mm,
                      const std::vector<std::uint8_t>& no_echo, std::vector<MeasurementRow>& rows);

}  // namespace tofcomp::io
