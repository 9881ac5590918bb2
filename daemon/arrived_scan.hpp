// A scan as it reached the loop over the link (daemon/scanner_link.hpp): its ranges in
// millimetres, the driver's sequence number and arrival time, and, when the link plays a
// recording, the time the recording gives it.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "realtime/raw_scan.hpp"

namespace tofcomp::daemon {

struct ArrivedScan {
  realtime::RawScan raw;  // time_s not yet set
  std::uint64_t sequence = 0;
  std::chrono::steady_clock::time_point received;
  std::optional<double> recorded_time_s;  // playing a recording: the scan's recorded time
};

}  // namespace tofcomp::daemon
