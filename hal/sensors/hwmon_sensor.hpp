// Linux hwmon temperature channels: <device>/temp<N>_input holds millidegrees Celsius as text
// (Documentation/hwmon/sysfs-interface). The device is either a directory
// (/sys/class/hwmon/hwmon2) or the contents of its `name` file ("lm75", "tmp102") under a root,
// since hwmon numbers follow probe order and can change between boots.
#pragma once

#include <filesystem>
#include <string>

#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

class HwmonSensor : public TemperatureSensor {
 public:
  // Reads <device_dir>/temp<channel>_input. Throws core::InvalidInput when device_dir is empty
  // or channel < 1 (hwmon numbers temperature channels from 1).
  HwmonSensor(std::filesystem::path device_dir, int channel,
              SensorClock clock = system_sensor_clock());

  // Reads channel `channel` of the device under `root` whose `name` file holds `name`. The
  // device is looked up at every read: none found is Missing, more than one is ReadError (give
  // the directory then). Throws core::InvalidInput when name is empty or channel < 1.
  static HwmonSensor by_name(std::string name, int channel,
                             std::filesystem::path root = "/sys/class/hwmon",
                             SensorClock clock = system_sensor_clock());

  // Missing when the directory or file is not there; ReadError with the errno text when the
  // read fails (EIO, ENODATA: the driver could not talk to the chip) and with the offending
  // content when it is not an integer.
  TemperatureReading read() override;
  std::string describe() const override;

 private:
  HwmonSensor(std::filesystem::path device_dir, std::string name, std::filesystem::path root,
              int channel, SensorClock clock);

  std::filesystem::path device_dir_;  // empty when looked up by name
  std::string name_;                  // empty when given by directory
  std::filesystem::path root_;
  int channel_;
  SensorClock clock_;
};

}  // namespace tofcomp::hal
