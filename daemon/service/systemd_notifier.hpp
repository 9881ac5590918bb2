// Tells the service manager how tofcompd is doing, through sd_notify(3): ready, a status line,
// watchdog pings, stopping, reloading; and reads the watchdog interval systemd asked for.
//
// The seam is systemd's own: libsystemd sends each message as one datagram to the AF_UNIX
// socket named by the NOTIFY_SOCKET environment variable. Without NOTIFY_SOCKET (a run outside
// systemd, or a unit that is not Type=notify) every call does nothing. A test points
// NOTIFY_SOCKET at a socket of its own and reads what was sent.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

namespace tofcomp::daemon::service {

enum class NotifyResult {
  Sent,       // the datagram went to NOTIFY_SOCKET
  NoManager,  // NOTIFY_SOCKET is not set: nothing to do
  Failed,     // NOTIFY_SOCKET is set but the datagram could not be sent (logged as a warning)
};

class SystemdNotifier {
 public:
  // True when NOTIFY_SOCKET is set, i.e. a service manager listens for notifications.
  bool enabled() const;

  NotifyResult ready();                        // READY=1: start-up finished
  NotifyResult status(std::string_view text);  // STATUS=text (line breaks become spaces)
  NotifyResult watchdog();                     // WATCHDOG=1: the event loop is alive
  NotifyResult stopping();                     // STOPPING=1: shutdown begun
  // RELOADING=1 with MONOTONIC_USEC (CLOCK_MONOTONIC now, which systemd 253+ asks for); send
  // ready() when the reload is over.
  NotifyResult reloading();

  // The watchdog interval (WatchdogSec=) when systemd watches this process, from
  // sd_watchdog_enabled(3); std::nullopt when it does not. Throws core::InvalidInput naming
  // WATCHDOG_USEC and WATCHDOG_PID when they are set but malformed.
  std::optional<std::chrono::microseconds> watchdog_interval() const;

  // How often to ping for a given watchdog interval: half of it, as sd_watchdog_enabled(3)
  // recommends.
  static std::chrono::microseconds ping_period(std::chrono::microseconds interval) {
    return interval / 2;
  }

 private:
  NotifyResult send(const std::string& state);
};

}  // namespace tofcomp::daemon::service
