// The bridge's loop: tofcompd's scans (a compact subscription to every beam on its socket) to
// LaserScan samples as they come, and every diagnostics period the daemon's `status` (asked on a
// second connection) with the scans' junction temperature and flagged beams to a
// DiagnosticArray. A daemon that goes away or restarts is reconnected to, reporting ERROR on
// /diagnostics meanwhile. One thread; returns when `stop` is set (within kPollInterval).
#pragma once

#include <atomic>
#include <chrono>
#include <ostream>

#include "bridges/ros2/bridge_config.hpp"

namespace tofcomp::bridges::ros2 {

// The longest the loop waits before it looks at `stop` again.
inline constexpr std::chrono::milliseconds kPollInterval{200};
// Between attempts to reach a daemon that cannot be reached.
inline constexpr std::chrono::milliseconds kReconnectInterval{1000};
// For hello, subscribe and status on the daemon's socket.
inline constexpr std::chrono::milliseconds kRequestTimeout{5000};

// Publishes until `stop`; progress and errors go to `log`. Throws core::Error when DDS cannot
// be set up (the domain, the topics).
void run_bridge(const BridgeConfig& config, const std::atomic<bool>& stop, std::ostream& log);

}  // namespace tofcomp::bridges::ros2
