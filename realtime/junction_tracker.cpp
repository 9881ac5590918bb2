#include "realtime/junction_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tofcomp::realtime {

JunctionTracker::JunctionTracker(const core::Calibration& calibration,
                                 JunctionTrackerSettings settings)
    : calibration_(calibration), settings_(settings) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(settings_.stale_after_s) || !positive(settings_.initial_case_std_c)) {
    throw core::InvalidInput(
        "junction tracker: stale_after_s and the initial case standard deviation must be positive");
  }
  calibration_.thermal.validate();
  calibration_.kalman_noise.validate();
}

void JunctionTracker::advance_to(double time_s) {
  if (!filter_ || time_s <= filter_time_s_) return;
  filter_->predict(time_s - filter_time_s_, power_on_ ? 1.0 : 0.0, ambient_c());
  filter_time_s_ = time_s;
}

void JunctionTracker::add_case_reading(double time_s, double case_c) {
  if (!std::isfinite(time_s) || !std::isfinite(case_c)) {
    throw core::InvalidInput("junction tracker: a case reading must be finite");
  }
  if (!filter_) {
    // The prior of the offline pipeline: the junction at rest on the heat the case sheds.
    filter_.emplace(calibration_.thermal, calibration_.kalman_noise,
                    core::prior_at_case_temperature(calibration_.thermal, case_c, ambient_c(),
                                                    settings_.initial_case_std_c));
    filter_time_s_ = time_s;
  }
  advance_to(time_s);
  filter_->update(case_c);
  last_reading_time_s_ = std::max(last_reading_time_s_, time_s);
  last_case_c_ = case_c;
}

void JunctionTracker::set_power(double time_s, bool on) {
  advance_to(time_s);  // the interval before the change had the old state
  if (on && !power_on_) powered_since_s_ = time_s;
  power_on_ = on;
}

void JunctionTracker::set_ambient(double time_s, double ambient_c) {
  if (!std::isfinite(time_s) || !std::isfinite(ambient_c)) {
    throw core::InvalidInput("junction tracker: an ambient reading must be finite");
  }
  advance_to(time_s);  // the interval before the reading had the old ambient
  ambient_c_ = ambient_c;
}

JunctionEstimate JunctionTracker::at(double time_s) const {
  JunctionEstimate e;
  e.ambient_c = ambient_c();
  if (!filter_) return e;
  core::ThermalKalmanFilter predicted = *filter_;
  if (time_s > filter_time_s_) {
    predicted.predict(time_s - filter_time_s_, power_on_ ? 1.0 : 0.0, ambient_c());
  }
  e.valid = true;
  e.junction_c = predicted.junction_mean_c();
  e.junction_std_c = predicted.junction_std_c();
  e.case_c = last_case_c_;
  e.stale = time_s - last_reading_time_s_ > settings_.stale_after_s;
  const Eigen::Vector2d& state = predicted.belief().mean;
  e.heating_rate_c_per_min =
      core::kSecondsPerMinute *
      core::junction_rate_c_per_s(calibration_.thermal, state[0], state[1], power_on_ ? 1.0 : 0.0);
  e.time_since_power_on_s = power_on_ ? std::max(0.0, time_s - powered_since_s_) : 0.0;
  return e;
}

}  // namespace tofcomp::realtime
