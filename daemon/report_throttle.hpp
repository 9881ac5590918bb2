// Reports of an event that can repeat many times a second (a scan refused, a connection turned
// away), at most one per interval so that a flood does not flood the log: the first, one for a
// reason unlike the last reported, and one once the interval has passed, each with how many
// were passed over since the report before. The caller gives the time.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace tofcomp::daemon {

class ReportThrottle {
 public:
  using Clock = std::chrono::steady_clock;

  explicit ReportThrottle(Clock::duration interval) : interval_(interval) {}

  // nullopt: pass this one over (it is counted); otherwise report it, told how many were
  // passed over since the last report.
  std::optional<std::uint64_t> report(Clock::time_point now, std::string_view reason = {}) {
    if (reported_at_ && now - *reported_at_ < interval_ && reason == reason_) {
      ++passed_over_;
      return std::nullopt;
    }
    reported_at_ = now;
    reason_ = reason;
    return std::exchange(passed_over_, 0);
  }

 private:
  Clock::duration interval_;
  std::optional<Clock::time_point> reported_at_;
  std::string reason_;
  std::uint64_t passed_over_ = 0;
};

}  // namespace tofcomp::daemon
