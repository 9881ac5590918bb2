#include "realtime/recording_replay.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "core/error.hpp"

namespace tofcomp::realtime {
void replay_recording(const io::MeasurementTable& table, const std::string& source,
                      CompensationPipeline& pipeline,
                      const std::function<void(const ipc::CompensatedScan&)>& on_scan) {
  replay_recording(table, source, pipeline,
                   [&](const RawScan&, const ipc::CompensatedScan& out) { on_scan(out); });
}

void replay_recording(
    const io::MeasurementTable& table, const std::string& source, CompensationPipeline& pipeline,
    const std::function<void(const RawScan& in, const ipc::CompensatedScan& out)>& on_scan) {
  const io::RecordingGeometry geometry = io::read_recording_geometry(table, source);
  RawScan scan;
  bool open = false;
  std::uint64_t scans = 0;
  const auto close_scan = [&] {
    if (!open) return;
    on_scan(scan, pipeline.on_scan(scan));
    open = false;
  };
  for (const io::MeasurementRow& row : table.rows) {
    if (row.range_mm) {
      const int beam = row.beam.value_or(0);
      if (beam < 0 || static_cast<std::size_t>(beam) >= geometry.beams) {
        throw core::InvalidInput(source + ":" + std::to_string(row.line) + ": beam " +
                                 std::to_string(beam) + " outside the recording's " +
                                 std::to_string(geometry.beams) + " beams");
      }
      // A scan is the rows of one time_s. Measured data may hold a beam twice at one time
      // (ties are allowed); the second range is a scan of its own, not written over the first.
      if (open && (row.time_s != scan.time_s || !scan.no_echo[static_cast<std::size_t>(beam)])) {
        close_scan();
      }
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
      scan.ranges_mm[static_cast<std::size_t>(beam)] = *row.range_mm;
      scan.no_echo[static_cast<std::size_t>(beam)] = 0;
      continue;
    }
    close_scan();
    if (row.power) pipeline.on_power(row.time_s, *row.power);
    if (row.ambient_c) pipeline.on_ambient(row.time_s, *row.ambient_c);
    if (row.case_temp_c) pipeline.on_case_reading(row.time_s, *row.case_temp_c);
  }
  close_scan();
}

}  // namespace tofcomp::realtime
