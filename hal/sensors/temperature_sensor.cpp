#include "hal/sensors/temperature_sensor.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::hal {

std::string_view to_string(ReadingValidity validity) {
  switch (validity) {
    case ReadingValidity::Valid:
      return "valid";
    case ReadingValidity::Implausible:
      return "implausible";
    case ReadingValidity::Stale:
      return "stale";
    case ReadingValidity::ReadError:
      return "read-error";
    case ReadingValidity::Missing:
      return "missing";
  }
  return "unknown";
}

TemperatureReading valid_reading(std::chrono::system_clock::time_point time, double celsius) {
  if (!std::isfinite(celsius))
    return invalid_reading(time, ReadingValidity::ReadError, "non-finite temperature value");
  return TemperatureReading{time, celsius, ReadingValidity::Valid, {}};
}

TemperatureReading invalid_reading(std::chrono::system_clock::time_point time,
                                   ReadingValidity validity, std::string detail) {
  if (validity == ReadingValidity::Valid)
    throw core::InvalidInput("invalid_reading: validity must not be Valid (detail: " + detail +
                             ")");
  return TemperatureReading{time, std::numeric_limits<double>::quiet_NaN(), validity,
                            std::move(detail)};
}

SensorClock system_sensor_clock() {
  return [] { return std::chrono::system_clock::now(); };
}

TemperatureSensor::~TemperatureSensor() = default;

}  // namespace tofcomp::hal
