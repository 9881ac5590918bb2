// The pipeline's clock: seconds on the host's monotonic clock since the daemon started, and the
// order of events on it. Owns the origin, the last event's time and the last scan's. An event's
// time is its own, or the last event's if that is later (a case reading is stamped when its read
// returned, and may reach the loop after a later scan): the pipeline and the recordings then see
// time run forwards only. Scans that arrived in one read share a timestamp; each gets a time of
// its own, so that a recording keeps them apart (io/recording_format.hpp).
#pragma once

#include <chrono>

namespace tofcomp::daemon {

class EventClock {
 public:
  using Clock = std::chrono::steady_clock;

  // The origin is now.
  EventClock();

  // Seconds from the origin to t.
  double seconds(Clock::time_point t) const;
  double now_s() const { return seconds(Clock::now()); }

  // An event at time_s: its time, not before the last event's; it becomes the last event's.
  double event_at(double time_s);
  // A scan at time_s: an event's time, and after the last scan's.
  double scan_at(double time_s);
  double last_event_s() const { return last_event_s_; }

 private:
  Clock::time_point origin_;
  double last_event_s_ = 0.0;
  double last_scan_s_ = -1.0;
};

}  // namespace tofcomp::daemon
