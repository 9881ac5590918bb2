// Which case-temperature backend to use and with what parameters, and the factory that builds
// it wrapped in the plausibility checks. The daemon's configuration reader fills the structs;
// nothing here parses files.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <variant>

#include "hal/sensors/i2c_tmp_sensor.hpp"
#include "hal/sensors/plausibility.hpp"
#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

// Linux hwmon: exactly one of `directory` (/sys/class/hwmon/hwmon2) and `name` (the device's
// `name` file, "lm75"), looked up under `root`.
struct HwmonSensorConfig {
  std::filesystem::path directory;
  std::string name;
  int channel = 1;
  std::filesystem::path root = "/sys/class/hwmon";
};

// TMP102 or TMP117 on /dev/i2c-N.
struct I2cSensorConfig {
  std::filesystem::path device = "/dev/i2c-1";
  int address = 0x48;
  TmpChip chip = TmpChip::Tmp102;
};

// DS18B20 through the w1 sysfs interface.
struct W1SensorConfig {
  std::string device_id;  // "28-0000075565b2"
  std::filesystem::path root = "/sys/bus/w1/devices";
};

// The value of the function given to make_temperature_sensor (the twin's case temperature).
struct SimulatedSensorConfig {
  std::string description = "simulated case temperature";
};

struct SensorConfig {
  std::variant<HwmonSensorConfig, I2cSensorConfig, W1SensorConfig, SimulatedSensorConfig> backend =
      SimulatedSensorConfig{};
  PlausibilityLimits limits;
};

// The configured backend inside a CheckedSensor. `simulated_source` is used only by the
// simulated backend and must be set for it. Throws core::InvalidInput naming the backend and
// field for a configuration that cannot work (hwmon with both or neither of directory and name,
// a bad channel, address, device id or limits). Opens nothing: a device that is absent shows
// up as Missing readings, not as an exception.
std::unique_ptr<TemperatureSensor> make_temperature_sensor(
    const SensorConfig& config, std::function<double()> simulated_source,
    SensorClock clock = system_sensor_clock());

}  // namespace tofcomp::hal
