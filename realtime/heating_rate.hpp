// The junction's heating rate dt^j/dt in real time, the covariate of the heating-hysteresis
// extension (core/model_extension.hpp). Offline the covariate is the least-squares slope of the
// RTS-smoothed junction over ±30 s around each range (core::covariate_values); a causal
// estimate cannot look ahead, so here it is the least-squares slope of the filtered junction
// (realtime/junction_tracker.hpp, at each scan) over the past 60 s: the same 60 s kernel,
// lagging the offline value by 30 s, on the filtered rather than the smoothed junction. Until
// two scans span a positive time the rate is 0.
#pragma once

#include <deque>
#include <utility>

namespace tofcomp::realtime {

inline constexpr double kHeatingRateWindowS = 60.0;

class HeatingRateEstimator {
 public:
  explicit HeatingRateEstimator(double window_s = kHeatingRateWindowS);

  // The junction estimate at time_s (non-decreasing; an earlier time restarts the history).
  // Throws core::InvalidInput on a non-finite value.
  void add(double time_s, double junction_c);
  // dt^j/dt in °C/min over the points of the last window_s seconds.
  double rate_c_per_minute() const;
  void reset() { points_.clear(); }

 private:
  double window_s_;
  std::deque<std::pair<double, double>> points_;  // time_s, junction_c
};

}  // namespace tofcomp::realtime
