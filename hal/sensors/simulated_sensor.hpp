// A temperature sensor fed by a function: the daemon connects it to the digital twin's case
// temperature so that the whole chain runs without hardware.
#pragma once

#include <functional>
#include <string>

#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

class SimulatedSensor : public TemperatureSensor {
 public:
  // Throws core::InvalidInput when `source` is empty.
  SimulatedSensor(std::function<double()> source, std::string description,
                  SensorClock clock = system_sensor_clock());

  // The source's value as Valid; a non-finite value or an exception from the source is
  // ReadError with its message.
  TemperatureReading read() override;
  std::string describe() const override { return description_; }

 private:
  std::function<double()> source_;
  std::string description_;
  SensorClock clock_;
};

}  // namespace tofcomp::hal
