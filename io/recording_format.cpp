#include "io/recording_format.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::io {
namespace {

std::string shortest(double value) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, r.ptr);
}

// Measured data with no geometry lines: as many beams as its rows name, the angles unknown.
RecordingGeometry geometry_of_rows(const MeasurementTable& table, const std::string& source) {
  constexpr double kUnknownAngle = std::numeric_limits<double>::quiet_NaN();
  std::size_t beams = 1;
  for (const MeasurementRow& row : table.rows) {
    if (!row.range_mm) continue;
    const int beam = row.beam.value_or(0);
    if (beam < 0 || static_cast<std::size_t>(beam) >= kMaxRecordingBeams) {
      throw core::InvalidInput(source + ":" + std::to_string(row.line) + ": beam " +
                               std::to_string(beam) + " outside 0.." +
                               std::to_string(kMaxRecordingBeams - 1));
    }
    beams = std::max(beams, static_cast<std::size_t>(beam) + 1);
  }
  return {beams, kUnknownAngle, kUnknownAngle};
}

// The '# beams' line's value as a count of beams; throws naming the line when it is none.
std::size_t whole_beams(double beams, const std::string& source) {
  if (beams < 1 || beams > static_cast<double>(kMaxRecordingBeams) || beams != std::floor(beams)) {
    throw core::InvalidInput(source + ": metadata '" + kRecordingBeamsKey +
                             "' must be a whole number of beams from 1 to " +
                             std::to_string(kMaxRecordingBeams));
  }
  return static_cast<std::size_t>(beams);
}

}  // namespace

RecordingGeometry read_recording_geometry(const MeasurementTable& table,
                                          const std::string& source) {
  std::optional<double> beams, start, resolution;
  for (const MetadataLine& m : table.metadata) {
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
  // The angles make a recording's geometry; a beam count alone is measured data's own metadata
  // (free keys, data-format.md: a logger's "# beams: 8"), the rows then name the beams.
  if (!start && !resolution) {
    RecordingGeometry rows = geometry_of_rows(table, source);
    if (beams) rows.beams = std::max(rows.beams, whole_beams(*beams, source));
    return rows;
  }
  if (!beams || !start || !resolution) {
    std::string missing;
    for (const auto& [line, key] :
         {std::pair{beams, kRecordingBeamsKey}, std::pair{start, kRecordingStartAngleKey},
          std::pair{resolution, kRecordingResolutionKey}}) {
      if (!line) missing += std::string(missing.empty() ? "" : ", ") + "'# " + key + "'";
    }
    throw core::InvalidInput(source + ": an incomplete recording geometry: the metadata lines '# " +
                             kRecordingBeamsKey + "', '# " + kRecordingStartAngleKey + "' and '# " +
                             kRecordingResolutionKey + "' go together (missing " + missing +
                             "); measured data has none of them");
  }
  return {whole_beams(*beams, source), *start, *resolution};
}

std::vector<std::string> recording_columns() {
  return {"time_s", "range_mm", "beam", "case_temp_c", "power"};
}

std::vector<MetadataLine> recording_metadata(std::size_t beams, double start_angle_deg,
                                             double resolution_deg) {
  return {{"sensor", "LMS200 (tofcompd recording)"},
          {kRecordingBeamsKey, std::to_string(beams)},
          {kRecordingStartAngleKey, shortest(start_angle_deg)},
          {kRecordingResolutionKey, shortest(resolution_deg)}};
}

void append_scan_rows(double time_s, const std::vector<double>& ranges_mm,
                      const std::vector<std::uint8_t>& no_echo, std::vector<MeasurementRow>& rows) {
  for (std::size_t b = 0; b < ranges_mm.size(); ++b) {
    if (no_echo[b]) continue;
    MeasurementRow row;
    row.time_s = time_s;
    row.range_mm = ranges_mm[b];
    row.beam = static_cast<int>(b);
    rows.push_back(std::move(row));
  }
}

}  // namespace tofcomp::io
