#include "daemon/scan_conversion.hpp"

#include "hal/lms2xx/measuring_mode.hpp"

namespace tofcomp::daemon {

realtime::RawScan to_raw_scan(const hal::lms2xx::HostScan& scan,
                              const hal::lms2xx::Variant& variant, double time_s) {
  realtime::RawScan raw;
  raw.device_sequence = scan.sequence;
  raw.time_s = time_s;
  raw.timestamp_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(scan.received_wall.time_since_epoch())
          .count();
  raw.rays = scan.rays;
  raw.start_angle_deg = variant.angle_deg == 100 ? 40.0 : 0.0;
  raw.resolution_deg = variant.resolution_centideg / 100.0;
  const auto& codes = scan.scan.distance_codes;
  raw.ranges_mm.resize(codes.size());
  raw.no_echo.resize(codes.size());
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const bool distance = hal::lms2xx::classify_distance_code(scan.measuring_mode, codes[i]) ==
                          hal::lms2xx::ValueStatus::Distance;
    raw.no_echo[i] = distance ? 0 : 1;
    raw.ranges_mm[i] = distance ? scan.scan.distance_mm(i) : 0.0;
  }
  return raw;
}

}  // namespace tofcomp::daemon
