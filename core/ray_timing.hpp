// When each ray of a scan was measured: the time of beam 0's ray and the scanner's sweep, from
// which any beam's time follows. The LMS 2xx host driver estimates it
// (hal/lms2xx/scan_timing.hpp); tofcompd publishes it with every scan (ipc/compensated_scan.hpp).
//
// A mirror turn sweeps the field once; a scan interlaces `interlaced_turns` turns, turn t
// measuring the beams i with i mod interlaced_turns = t. Beam i's ray comes
//   (i mod n)·turn_period_ns + ⌊i / n⌋·ray_interval_ns
// after beam 0's (n = interlaced_turns), ray_interval_ns apart within one turn.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tofcomp::core {

// The most turns a scan interlaces (the LMS 2xx at 0.25°): more, in a scan read from outside, is
// a malformed scan.
inline constexpr std::uint32_t kMaxInterlacedTurns = 4;

inline constexpr std::int64_t kNsPerSecond = 1'000'000'000;

struct RayTiming {
  std::int64_t first_ray_ns = 0;  // beam 0's ray, CLOCK_REALTIME ns since the epoch; 0: unknown
  double ray_interval_ns = 0.0;   // between consecutive rays of one turn
  double turn_period_ns = 0.0;    // one mirror turn
  std::uint32_t interlaced_turns = 0;  // turns one scan takes (1, 2 or 4); 0: unknown

  bool known() const { return interlaced_turns > 0; }
  // Beam `beam`'s ray after beam 0's, in ns; 0 when the timing is unknown.
  double beam_offset_ns(std::size_t beam) const {
    if (!known()) return 0.0;
    return static_cast<double>(beam % interlaced_turns) * turn_period_ns +
           static_cast<double>(beam / interlaced_turns) * ray_interval_ns;
  }
};

}  // namespace tofcomp::core
