#include "hal/sensors/simulated_sensor.hpp"

#include <exception>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::hal {

SimulatedSensor::SimulatedSensor(std::function<double()> source, std::string description,
                                 SensorClock clock)
    : source_(std::move(source)), description_(std::move(description)), clock_(std::move(clock)) {
  if (!source_)
    throw core::InvalidInput("simulated sensor '" + description_ + "': no temperature source");
  if (!clock_) throw core::InvalidInput("simulated sensor '" + description_ + "': no clock");
}

TemperatureReading SimulatedSensor::read() {
  double celsius = 0.0;
  try {
    celsius = source_();
  } catch (const std::exception& error) {
    return invalid_reading(clock_(), ReadingValidity::ReadError,
                           description_ + ": source failed: " + error.what());
  }
  TemperatureReading reading = valid_reading(clock_(), celsius);
  if (!reading.valid()) reading.detail = description_ + ": " + reading.detail;
  return reading;
}

}  // namespace tofcomp::hal
