// The case-temperature sensor seam: one reading, with its time and a validity that says whether
// the number may be used. Backends (hwmon, 1-Wire DS18B20, i2c-dev TMP102/TMP117, simulated)
// implement TemperatureSensor; CheckedSensor (plausibility.hpp) adds range, rate and age checks.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <string_view>

namespace tofcomp::hal {

enum class ReadingValidity {
  Valid,        // celsius is a measured temperature
  Implausible,  // the backend answered, but the value is out of range or jumped impossibly
  Stale,        // no valid reading for longer than the allowed age (plausibility.hpp)
  ReadError,    // the device is there but the read failed (I/O error, CRC, unparsable content)
  Missing,      // the device (directory, file, bus) does not exist
};

// "valid", "implausible", "stale", "read-error", "missing".
std::string_view to_string(ReadingValidity validity);

struct TemperatureReading {
  std::chrono::system_clock::time_point time;
  // NaN unless validity is Valid: an invalid reading never carries a number on.
  double celsius;
  ReadingValidity validity;
  // Empty when valid; otherwise what went wrong and where (file, device, errno text, content).
  std::string detail;

  bool valid() const { return validity == ReadingValidity::Valid; }
};

// A valid reading; a non-finite `celsius` gives a ReadError instead, so NaN never passes as
// Valid.
TemperatureReading valid_reading(std::chrono::system_clock::time_point time, double celsius);
// An invalid reading (celsius NaN) with the given validity, which must not be Valid.
TemperatureReading invalid_reading(std::chrono::system_clock::time_point time,
                                   ReadingValidity validity, std::string detail);

// Where readings take their time from; injected so that tests control time.
using SensorClock = std::function<std::chrono::system_clock::time_point()>;
// std::chrono::system_clock::now.
SensorClock system_sensor_clock();

class TemperatureSensor {
 public:
  virtual ~TemperatureSensor();

  // One reading. Never throws for a sensor failure: failures come back as an invalid reading.
  // May block: a DS18B20 conversion takes up to 750 ms at 12-bit resolution (datasheet,
  // tCONV), an I2C transfer or a hwmon driver may stall on a bus; callers run read() off the
  // event loop (a worker thread), never inside an Asio handler.
  virtual TemperatureReading read() = 0;

  // What the sensor is and where, for logs and error messages: "hwmon lm75 temp1 (...)".
  virtual std::string describe() const = 0;
};

}  // namespace tofcomp::hal
