#include "realtime/heating_rate.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tofcomp::realtime {

HeatingRateEstimator::HeatingRateEstimator(double window_s) : window_s_(window_s) {
  if (!(std::isfinite(window_s_) && window_s_ > 0.0)) {
    throw core::InvalidInput("heating rate: the window must be positive");
  }
}

void HeatingRateEstimator::add(double time_s, double junction_c) {
  if (!std::isfinite(time_s) || !std::isfinite(junction_c)) {
    throw core::InvalidInput("heating rate: a junction estimate must be finite");
  }
  if (!points_.empty() && time_s < points_.back().first) points_.clear();
  points_.emplace_back(time_s, junction_c);
  while (time_s - points_.front().first > window_s_) points_.pop_front();
}

double HeatingRateEstimator::rate_c_per_minute() const {
  if (points_.size() < 2) return 0.0;
  // Centred on the means: no cancellation against the clock or a 40 °C offset.
  double mean_t = 0.0;
  double mean_j = 0.0;
  for (const auto& [t, j] : points_) {
    mean_t += t;
    mean_j += j;
  }
  const auto n = static_cast<double>(points_.size());
  mean_t /= n;
  mean_j /= n;
  double stt = 0.0;
  double stj = 0.0;
  for (const auto& [t, j] : points_) {
    stt += (t - mean_t) * (t - mean_t);
    stj += (t - mean_t) * (j - mean_j);
  }
  return stt > 0.0 ? 60.0 * stj / stt : 0.0;
}

}  // namespace tofcomp::realtime
