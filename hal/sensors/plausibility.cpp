#include "hal/sensors/plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::hal {
namespace {

std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

void check_plausibility_limits(const PlausibilityLimits& limits) {
  const auto fail = [](const std::string& what) {
    throw core::InvalidInput("plausibility limits: " + what);
  };
  if (!std::isfinite(limits.min_c) || !std::isfinite(limits.max_c))
    fail("min_c and max_c must be finite");
  if (!(limits.min_c < limits.max_c))
    fail("min_c (" + number(limits.min_c) + ") must be below max_c (" + number(limits.max_c) + ")");
  if (!std::isfinite(limits.max_rate_c_per_s) || !(limits.max_rate_c_per_s > 0.0))
    fail("max_rate_c_per_s must be finite and positive, got " + number(limits.max_rate_c_per_s));
  if (!std::isfinite(limits.jump_allowance_c) || limits.jump_allowance_c < 0.0)
    fail("jump_allowance_c must be finite and not negative, got " +
         number(limits.jump_allowance_c));
  if (!std::isfinite(limits.max_age.count()) || !(limits.max_age.count() > 0.0))
    fail("max_age must be finite and positive, got " + number(limits.max_age.count()) + " s");
}

CheckedSensor::CheckedSensor(std::unique_ptr<TemperatureSensor> inner, PlausibilityLimits limits,
                             SensorClock clock)
    : inner_(std::move(inner)), limits_(limits), clock_(std::move(clock)) {
  if (!inner_) throw core::InvalidInput("CheckedSensor: no backend sensor given");
  if (!clock_) throw core::InvalidInput("CheckedSensor for " + inner_->describe() + ": no clock");
  check_plausibility_limits(limits_);
}

TemperatureReading CheckedSensor::read() {
  TemperatureReading reading = inner_->read();
  const auto now = clock_();
  reading.time = now;

  if (reading.valid()) {
    const double t = reading.celsius;
    if (t < limits_.min_c || t > limits_.max_c) {
      reading = invalid_reading(now, ReadingValidity::Implausible,
                                number(t) + " °C is outside [" + number(limits_.min_c) + ", " +
                                    number(limits_.max_c) + "] °C");
    } else if (last_valid_) {
      const double seconds =
          std::max(0.0, std::chrono::duration<double>(now - last_valid_->time).count());
      const double change = std::abs(t - last_valid_->celsius);
      const double allowed = limits_.jump_allowance_c + limits_.max_rate_c_per_s * seconds;
      if (change > allowed)
        reading = invalid_reading(now, ReadingValidity::Implausible,
                                  "jump of " + number(change) + " °C in " + number(seconds) +
                                      " s from the last valid " + number(last_valid_->celsius) +
                                      " °C (at most " + number(allowed) + " °C allowed)");
    }
  }

  if (reading.valid()) {
    last_valid_ = LastValid{now, reading.celsius};
    return reading;
  }
  if (last_valid_) {
    const std::chrono::duration<double> age = now - last_valid_->time;
    if (age > limits_.max_age)
      return invalid_reading(now, ReadingValidity::Stale,
                             "last valid reading " + number(age.count()) + " s ago (max " +
                                 number(limits_.max_age.count()) + " s); now " +
                                 std::string(to_string(reading.validity)) + ": " + reading.detail);
  }
  return reading;
}

std::string CheckedSensor::describe() const {
  return inner_->describe();
}

}  // namespace tofcomp::hal
