// SystemdNotifier over libsystemd's sd_notify and sd_watchdog_enabled.
#include "daemon/service/systemd_notifier.hpp"

#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "core/error.hpp"

namespace tofcomp::daemon::service {
namespace {

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value == nullptr ? "(unset)" : "'" + std::string(value) + "'";
}

// A status is one assignment of a newline-separated message: a line break inside it would start
// another assignment, so it becomes a space.
std::string one_line(std::string_view text) {
  std::string line(text);
  for (char& c : line) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return line;
}

std::uint64_t monotonic_now_usec() {
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::uint64_t>(now.tv_sec) * 1'000'000u +
         static_cast<std::uint64_t>(now.tv_nsec) / 1'000u;
}

}  // namespace

bool SystemdNotifier::enabled() const {
  return std::getenv("NOTIFY_SOCKET") != nullptr;
}

NotifyResult SystemdNotifier::ready() {
  return send("READY=1");
}

NotifyResult SystemdNotifier::status(std::string_view text) {
  return send("STATUS=" + one_line(text));
}

NotifyResult SystemdNotifier::watchdog() {
  return send("WATCHDOG=1");
}

NotifyResult SystemdNotifier::stopping() {
  return send("STOPPING=1");
}

NotifyResult SystemdNotifier::reloading() {
  return send("RELOADING=1\nMONOTONIC_USEC=" + std::to_string(monotonic_now_usec()));
}

std::optional<std::chrono::microseconds> SystemdNotifier::watchdog_interval() const {
  std::uint64_t usec = 0;
  const int r = ::sd_watchdog_enabled(0, &usec);
  if (r < 0) {
    throw core::InvalidInput(
        "systemd watchdog environment is malformed (WATCHDOG_USEC=" + environment("WATCHDOG_USEC") +
        ", WATCHDOG_PID=" + environment("WATCHDOG_PID") + "): " + std::strerror(-r));
  }
  if (r == 0) return std::nullopt;
  return std::chrono::microseconds(static_cast<std::chrono::microseconds::rep>(usec));
}

NotifyResult SystemdNotifier::send(const std::string& state) {
  const int r = ::sd_notify(0, state.c_str());
  if (r > 0) return NotifyResult::Sent;
  if (r == 0) return NotifyResult::NoManager;
  std::string first_line = state.substr(0, state.find('\n'));
  spdlog::warn("cannot notify systemd of {} through NOTIFY_SOCKET={}: {}", first_line,
               environment("NOTIFY_SOCKET"), std::strerror(-r));
  return NotifyResult::Failed;
}

}  // namespace tofcomp::daemon::service
