// What the service manager is told (systemd's notify protocol, daemon/service/): the status line,
// readiness once the first compensated scan is published, the watchdog's pings, reloads and the
// stop. Owns the notifier, the status text, whether readiness was sent and the watchdog's timing.
#pragma once

#include <chrono>
#include <optional>
#include <string>

#include "daemon/service/systemd_notifier.hpp"

namespace tofcomp::daemon {

class ServiceStatus {
 public:
  using Clock = std::chrono::steady_clock;

  // Pings from now on at half the watchdog interval, when systemd watches the process.
  void start_watchdog();
  // A ping, when one is due (on the loop: a stuck loop stops the pings).
  void watchdog(Clock::time_point now);

  void set(const std::string& text);
  const std::string& text() const { return text_; }
  // The status of a scanner that runs: waiting for the first scan, or publishing.
  void show_scan_state();
  // A scan was published: the first one makes the service ready; after refusals the status is
  // publishing again.
  void scan_published();
  // The compensation path refused a scan: the status says so, and why, until one is published.
  void scan_refused(const std::string& why);

  void reloading();
  void reloaded();
  void stopping();

 private:
  service::SystemdNotifier notifier_;
  std::string text_;
  bool ready_sent_ = false;
  bool refusing_ = false;
  std::optional<Clock::duration> watchdog_period_;
  Clock::time_point last_watchdog_{};
};

}  // namespace tofcomp::daemon
