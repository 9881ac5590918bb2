// A DS18B20 1-Wire thermometer through the kernel's w1 sysfs interface (w1_therm):
// <root>/<device id>/w1_slave holds the nine scratchpad bytes with the CRC verdict and the
// temperature in millidegrees:
//   72 01 4b 46 7f ff 0e 10 57 : crc=57 YES
//   72 01 4b 46 7f ff 0e 10 57 t=23125
// Reading the file starts a conversion and blocks until it ends (up to 750 ms at 12 bits,
// datasheet tCONV).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

class W1Ds18b20Sensor : public TemperatureSensor {
 public:
  // `device_id` is the w1 name of the device, "28-" and the 12 hex digits of its serial number
  // (family code 0x28 is the DS18B20, datasheet). Throws core::InvalidInput for any other form.
  explicit W1Ds18b20Sensor(std::string device_id,
                           std::filesystem::path root = "/sys/bus/w1/devices",
                           SensorClock clock = system_sensor_clock());

  // Missing when the device directory or w1_slave is not there; ReadError when the read fails,
  // the CRC does not match ("crc=.. NO"), the scratchpad is all zeros (a device that did not
  // answer: zeros pass the CRC), the temperature is the power-on reset value 85.0 °C (the
  // conversion did not run, datasheet: temperature register reset value 0550h), or the
  // content is not in the form above.
  TemperatureReading read() override;
  std::string describe() const override;

 private:
  std::string device_id_;
  std::filesystem::path root_;
  SensorClock clock_;
};

// The reading in a w1_slave text, for read() and the tests. `where` names the file in the
// details.
TemperatureReading parse_w1_slave(std::string_view content, const std::string& where,
                                  std::chrono::system_clock::time_point time);

}  // namespace tofcomp::hal
