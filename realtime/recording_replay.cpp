#include "realtime/recording_replay.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "io/measurement_columns.hpp"

namespace tofcomp::realtime {
namespace {

std::string shortest(double value) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, r.ptr);
}

}  // namespace

RecordingGeometry read_recording_geometry(const io::MeasurementTable& table,
                                          const std::string& source) {
  std::optional<double> beams, start, resolution;
  for (const io::MetadataLine& m : table.metadata) {
    double value = 0.0;
    const auto r = std::from_chars(m.value.data(), m.value.data() + m.value.size(), value);
    const bool number = r.ec == std::errc() && r.ptr == m.value.data() + m.value.size();
    std::optional<double>* target = m.key == kRecordingBeamsKey        ? &beams
                                    : m.key == kRecordingStartAngleKey ? &start
                                    : m.key == kRecordingResolutionKey ? &resolution
                                                                       : nullptr;
    if (!target) continue;
    if (!number || !std::isfinite(value)) {
      throw core::InvalidInput(source + ": metadata '" + m.key + ": " + m.value +
                               "' is not a number");
    }
    *target = value;
  }
  if (!beams || !start || !resolution) {
    throw core::InvalidInput(source + ": not a tofcompd recording: the metadata lines '# " +
                             kRecordingBeamsKey + "', '# " + kRecordingStartAngleKey + "' and '# " +
                             kRecordingResolutionKey + "' are required");
  }
  if (*beams < 1 || *beams > 65535 || *beams != std::floor(*beams)) {
    throw core::InvalidInput(source + ": metadata '" + kRecordingBeamsKey +
                             "' must be a whole number of beams from 1");
  }
  return {static_cast<std::size_t>(*beams), *start, *resolution};
}

std::vector<std::string> recording_columns() {
  return {"time_s", "range_mm", "beam", "case_temp_c", "power"};
}

std::vector<io::MetadataLine> recording_metadata(std::size_t beams, double start_angle_deg,
                                                 double resolution_deg) {
  return {{"sensor", "LMS200 (tofcompd recording)"},
          {kRecordingBeamsKey, std::to_string(beams)},
          {kRecordingStartAngleKey, shortest(start_angle_deg)},
          {kRecordingResolutionKey, shortest(resolution_deg)}};
}

void append_scan_rows(const RawScan& scan, std::vector<io::MeasurementRow>& rows) {
  for (std::size_t b = 0; b < scan.ranges_mm.size(); ++b) {
    if (scan.no_echo[b]) continue;
    io::MeasurementRow row;
    row.time_s = scan.time_s;
    row.range_mm = scan.ranges_mm[b];
    row.beam = static_cast<int>(b);
    rows.push_back(std::move(row));
  }
}

void replay_recording(const io::MeasurementTable& table, const std::string& source,
                      CompensationPipeline& pipeline,
                      const std::function<void(const ipc::CompensatedScan&)>& on_scan) {
  const RecordingGeometry geometry = read_recording_geometry(table, source);
  RawScan scan;
  bool open = false;
  std::uint64_t scans = 0;
  const auto close_scan = [&] {
    if (!open) return;
    on_scan(pipeline.on_scan(scan));
    open = false;
  };
  for (const io::MeasurementRow& row : table.rows) {
    if (row.range_mm) {
      if (open && row.time_s != scan.time_s) close_scan();
      if (!open) {
        scan = RawScan{};
        scan.device_sequence = scans++;
        scan.time_s = row.time_s;
        scan.start_angle_deg = geometry.start_angle_deg;
        scan.resolution_deg = geometry.resolution_deg;
        scan.ranges_mm.assign(geometry.beams, 0.0);
        scan.no_echo.assign(geometry.beams, 1);
        open = true;
      }
      const int beam = row.beam.value_or(0);
      if (beam < 0 || static_cast<std::size_t>(beam) >= geometry.beams) {
        throw core::InvalidInput(source + ":" + std::to_string(row.line) + ": beam " +
                                 std::to_string(beam) + " outside the recording's " +
                                 std::to_string(geometry.beams) + " beams");
      }
      scan.ranges_mm[static_cast<std::size_t>(beam)] = *row.range_mm;
      scan.no_echo[static_cast<std::size_t>(beam)] = 0;
      continue;
    }
    close_scan();
    if (row.power) pipeline.on_power(row.time_s, *row.power);
    if (row.case_temp_c) pipeline.on_case_reading(row.time_s, *row.case_temp_c);
  }
  close_scan();
}

}  // namespace tofcomp::realtime
