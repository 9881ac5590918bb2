#include "daemon/service_status.hpp"

#include <spdlog/spdlog.h>

namespace tofcomp::daemon {

namespace {
constexpr const char* kWaitingStatus = "waiting for the first scan";
constexpr const char* kPublishingStatus = "publishing compensated scans";
constexpr const char* kRefusingStatus = "refusing scans: ";
}  // namespace

void ServiceStatus::start_watchdog() {
  if (const auto interval = notifier_.watchdog_interval()) {
    watchdog_period_ = service::SystemdNotifier::ping_period(*interval);
  }
}

void ServiceStatus::watchdog(Clock::time_point now) {
  if (watchdog_period_ && now - last_watchdog_ >= *watchdog_period_) {
    notifier_.watchdog();
    last_watchdog_ = now;
  }
}

void ServiceStatus::set(const std::string& text) {
  text_ = text;
  notifier_.status(text);
}

void ServiceStatus::show_scan_state() {
  set(ready_sent_ ? kPublishingStatus : kWaitingStatus);
}

void ServiceStatus::scan_published() {
  if (refusing_) {
    refusing_ = false;
    set(kPublishingStatus);
  }
  if (ready_sent_) return;
  ready_sent_ = true;
  notifier_.ready();
  spdlog::info("first compensated scan published: ready");
  set(kPublishingStatus);
}

void ServiceStatus::scan_refused(const std::string& why) {
  const std::string text = std::string(kRefusingStatus) + why;
  refusing_ = true;
  if (text != text_) set(text);
}

void ServiceStatus::reloading() {
  notifier_.reloading();
}

void ServiceStatus::reloaded() {
  notifier_.ready();
}

void ServiceStatus::stopping() {
  notifier_.stopping();
}

}  // namespace tofcomp::daemon
