#include "bridges/ros2/laser_scan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/lms200_limits.hpp"
#include "core/ray_timing.hpp"

namespace tofcomp::bridges::ros2 {

namespace {

constexpr double kMmPerMetre = 1000.0;
constexpr double kNsPerSecondReal = static_cast<double>(core::kNsPerSecond);

float radians(double degrees) { return static_cast<float>(degrees * std::numbers::pi / 180.0); }

core::RayTiming ray_timing_of(const client::ScanInfo& info) {
  return core::RayTiming{info.first_ray_ns, info.ray_interval_ns, info.turn_period_ns,
                         info.interlaced_turns};
}

}  // namespace

float ros_range(const client::Beam& beam) {
  if ((beam.flags & TOFCOMP_FLAG_NO_ECHO) != 0) return std::numeric_limits<float>::infinity();
  if (!std::isfinite(beam.compensated_mm)) return std::numeric_limits<float>::quiet_NaN();
  return static_cast<float>(beam.compensated_mm / kMmPerMetre);
}

LaserScanValues laser_scan_from(const client::Scan& scan) {
  const client::ScanInfo& info = scan.info;
  const std::size_t count = scan.beams.size();
  if (count == 0 || count != info.beam_count || scan.beams.front().index != 0) {
    throw core::InvalidInput("scan " + std::to_string(info.sequence) + " carries " +
                             std::to_string(count) + " of its " + std::to_string(info.beam_count) +
                             " beams; a LaserScan needs them all");
  }
  if (!(info.resolution_deg > 0.0) || !std::isfinite(info.start_angle_deg)) {
    throw core::InvalidInput("scan " + std::to_string(info.sequence) +
                             " has no valid angles (resolution " +
                             std::to_string(info.resolution_deg) + "°)");
  }
  LaserScanValues out;
  out.angle_increment = radians(info.resolution_deg);
  out.angle_min = radians(info.start_angle_deg - kForwardAngleDeg);
  out.angle_max = radians(info.start_angle_deg + static_cast<double>(count - 1) * info.resolution_deg -
                          kForwardAngleDeg);
  out.range_min = static_cast<float>(core::lms200::kMinReferenceMm / kMmPerMetre);
  out.range_max = static_cast<float>(core::lms200::kMaxRangeMm / kMmPerMetre);

  const core::RayTiming rays = ray_timing_of(info);
  if (rays.known()) {
    out.stamp_ns = rays.first_ray_ns;
    // The scan's rays span from beam 0's to the last measured; spread evenly over the beams, so
    // that stamp + i × time_increment runs from the first ray to the last. Exact for a scan of one
    // turn; for interlaced turns each beam's own time is (i mod n) turns off the linear order
    // (docs/integration.md, "time_increment").
    double sweep_ns = 0.0;
    for (std::size_t i = 0; i < count; ++i) sweep_ns = std::max(sweep_ns, rays.beam_offset_ns(i));
    out.time_increment =
        count > 1 ? static_cast<float>(sweep_ns / static_cast<double>(count - 1) / kNsPerSecondReal) : 0.0f;
    out.scan_time = static_cast<float>(static_cast<double>(rays.interlaced_turns) *
                                       rays.turn_period_ns / kNsPerSecondReal);
  } else {
    out.stamp_ns = info.timestamp_ns;  // a recording's scan: only its arrival is known
  }
  out.ranges.reserve(count);
  for (const client::Beam& beam : scan.beams) out.ranges.push_back(ros_range(beam));
  return out;
}

}  // namespace tofcomp::bridges::ros2
