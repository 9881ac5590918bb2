// Plausibility checks on top of any temperature backend: a value outside the physical range, a
// jump faster than a case can heat or cool, and a sensor that has given nothing valid for too
// long are marked, so that the estimator never takes them as temperatures.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

struct PlausibilityLimits {
  // Accepted range, inclusive. The defaults are the TMP102's and DS18B20's specified range
  // (-40..125 °C for the TMP102, -55..125 °C for the DS18B20, datasheets).
  double min_c = -40.0;
  double max_c = 125.0;
  // Largest believable rate of change against the last valid reading.
  double max_rate_c_per_s = 5.0;
  // A change up to this size is always accepted, however short the interval: it covers the
  // quantization step (0.0625 °C for DS18B20 and TMP102) and two reads close together.
  double jump_allowance_c = 0.5;
  // A failing sensor turns Stale once its last valid reading is older than this.
  std::chrono::duration<double> max_age{10.0};
};

// Throws core::InvalidInput naming the field when the limits are not usable (non-finite,
// min_c >= max_c, a non-positive rate or age, a negative allowance).
void check_plausibility_limits(const PlausibilityLimits& limits);

// Wraps a backend and classifies each of its readings; the time of every reading is the
// wrapper's clock when the backend returned. In order:
//  1. A Valid backend reading outside [min_c, max_c] becomes Implausible.
//  2. A Valid backend reading that differs from the last valid one by more than
//     jump_allowance_c + max_rate_c_per_s * (seconds between them) becomes Implausible.
//     Implausible readings do not replace the last valid one, so a real step is accepted once
//     enough time has passed for the rate to allow it.
//  3. Any reading that is not Valid after 1-2 (the backend's ReadError or Missing, or an
//     Implausible one) becomes Stale when a valid reading was seen before and it is older than
//     max_age; its detail keeps the underlying cause. Before max_age has passed the backend's
//     own validity stays (a repeated failure after a valid reading is still ReadError). Before
//     the first valid reading, nothing is Stale: a sensor that never worked reports its own
//     failure (Missing, ReadError).
class CheckedSensor : public TemperatureSensor {
 public:
  // Throws core::InvalidInput when `inner` is null or the limits are not usable.
  CheckedSensor(std::unique_ptr<TemperatureSensor> inner, PlausibilityLimits limits = {},
                SensorClock clock = system_sensor_clock());

  TemperatureReading read() override;
  std::string describe() const override;

  const PlausibilityLimits& limits() const { return limits_; }

 private:
  struct LastValid {
    std::chrono::system_clock::time_point time;
    double celsius;
  };

  std::unique_ptr<TemperatureSensor> inner_;
  PlausibilityLimits limits_;
  SensorClock clock_;
  std::optional<LastValid> last_valid_;
};

}  // namespace tofcomp::hal
