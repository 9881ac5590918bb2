#include "cli/scan_text.hpp"

#include <cmath>
#include <cstdio>

#include "io/utc_time.hpp"

namespace tofcomp::cli {

namespace {

// A value with a printf format, or "-" for one that does not exist (NaN, or infinite).
std::string number(double value, const char* format) {
  if (!std::isfinite(value)) return "-";
  char text[48];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string joined_flag_names(std::uint16_t flags) {
  std::string text;
  for (const std::string& name : ipc::beam_flag_names(flags)) {
    text += (text.empty() ? "" : ",") + name;
  }
  return text.empty() ? "-" : text;
}

// When the scan's first ray was measured, relative to its arrival (docs/protocol.md "Time").
std::string first_ray_text(const ipc::CompensatedScan& scan) {
  if (!scan.rays.known()) return "";
  constexpr double kNanosecondsPerMillisecond = 1e6;
  const double before_ms =
      static_cast<double>(scan.timestamp_ns - scan.rays.first_ray_ns) / kNanosecondsPerMillisecond;
  return " (first ray " + number(before_ms, "%.1f") + " ms before)";
}

}  // namespace

std::string scan_text(const ipc::CompensatedScan& scan, ipc::socket::BeamSpan span) {
  std::string text =
      "scan " + std::to_string(scan.sequence) + " (device " + std::to_string(scan.device_sequence) +
      ") at " + io::utc_timestamp(scan.timestamp_ns, 3) + first_ray_text(scan) + "; junction " +
      number(scan.junction_c, "%.2f") + " ± " + number(scan.junction_std_c, "%.2f") + " °C, case " +
      number(scan.case_c, "%.2f") + " °C; calibration " + std::to_string(scan.calibration_id) +
      "; beams " +
      (span.count == 0
           ? std::string("none")
           : std::to_string(span.first) + ".." + std::to_string(span.first + span.count - 1)) +
      " of " + std::to_string(scan.beams.size()) + "\n";
  text += " beam   angle°    raw mm   comp. mm  window mm   std mm  mode  flags\n";
  const double start = std::isfinite(scan.start_angle_deg) ? scan.start_angle_deg : 0.0;
  const double step = std::isfinite(scan.resolution_deg) ? scan.resolution_deg : 0.0;
  for (std::size_t b = span.first; b < span.first + span.count; ++b) {
    const ipc::BeamValue& v = scan.beams[b];
    const std::string mode = v.mode_count > 0 ? std::to_string(v.most_probable_mode) : "-";
    char row[200];
    std::snprintf(row, sizeof row, "%5zu %8.2f %9s %10s %10s %8s %5s  %s\n", b,
                  start + step * static_cast<double>(b), number(v.raw_mm, "%.1f").c_str(),
                  number(v.compensated_mm, "%.2f").c_str(), number(v.window_mm, "%.2f").c_str(),
                  number(v.window_std_mm, "%.2f").c_str(), mode.c_str(),
                  joined_flag_names(v.flags).c_str());
    text += row;
  }
  return text;
}

}  // namespace tofcomp::cli
