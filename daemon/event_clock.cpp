#include "daemon/event_clock.hpp"

#include <algorithm>
#include <cmath>

namespace tofcomp::daemon {

EventClock::EventClock() : origin_(Clock::now()) {}

double EventClock::seconds(Clock::time_point t) const {
  return std::chrono::duration<double>(t - origin_).count();
}

double EventClock::event_at(double time_s) {
  last_event_s_ = std::max(time_s, last_event_s_);
  return last_event_s_;
}

double EventClock::scan_at(double time_s) {
  double t = event_at(time_s);
  if (t <= last_scan_s_) t = std::nextafter(last_scan_s_, INFINITY);
  last_scan_s_ = t;
  last_event_s_ = t;
  return t;
}

}  // namespace tofcomp::daemon
