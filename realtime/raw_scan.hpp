// One scan as the daemon receives it, before compensation: the ranges of every beam, which
// beams had no echo, and when it arrived. The LMS 200 driver's scans and a recording's rows
// (realtime/recording_replay.hpp) both become these.
#pragma once

#include <cstdint>
#include <vector>

#include "core/ray_timing.hpp"

namespace tofcomp::realtime {

struct RawScan {
  std::uint64_t device_sequence = 0;  // the source's own scan counter
  double time_s = 0.0;                // the pipeline's clock (seconds since the daemon's start)
  std::int64_t timestamp_ns = 0;      // wall clock at arrival, for publication
  core::RayTiming rays;               // when its rays were measured; unknown for a recording's
  double start_angle_deg = 0.0;
  double resolution_deg = 0.0;
  std::vector<double> ranges_mm;      // per beam; ignored where no_echo
  std::vector<std::uint8_t> no_echo;  // per beam: 1 when the device reported no range
};

}  // namespace tofcomp::realtime
