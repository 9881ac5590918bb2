// TI TMP102 and TMP117 thermometers on raw i2c-dev: write the pointer register 0x00
// (temperature), read its two bytes, most significant first. The bus is a narrow seam
// (I2cBus) so that the conversions are tested without hardware; LinuxI2cBus is the real one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "core/error.hpp"
#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

// A failed bus operation, with the errno the kernel gave.
class I2cError : public core::Error {
 public:
  I2cError(const std::string& what, int error_number)
      : core::Error(what), error_number_(error_number) {}
  int error_number() const { return error_number_; }

 private:
  int error_number_;
};

class I2cBus {
 public:
  virtual ~I2cBus();
  // Each throws I2cError on failure.
  virtual void set_address(int address) = 0;
  virtual void write(std::span<const std::uint8_t> bytes) = 0;
  virtual void read(std::span<std::uint8_t> bytes) = 0;
  // The bus for messages: "/dev/i2c-1".
  virtual std::string describe() const = 0;
};

// /dev/i2c-N through the kernel's i2c-dev: open(O_RDWR), ioctl(I2C_SLAVE), write(), read().
// The device is opened at the first operation and kept open, so a bus that appears after start
// (a module loaded late) is found; an open that fails throws I2cError with the path and errno
// (ENOENT when there is no such bus). A short transfer is an I2cError with EIO.
class LinuxI2cBus : public I2cBus {
 public:
  explicit LinuxI2cBus(std::filesystem::path device);
  ~LinuxI2cBus() override;
  LinuxI2cBus(const LinuxI2cBus&) = delete;
  LinuxI2cBus& operator=(const LinuxI2cBus&) = delete;

  void set_address(int address) override;
  void write(std::span<const std::uint8_t> bytes) override;
  void read(std::span<std::uint8_t> bytes) override;
  std::string describe() const override { return device_.string(); }

 private:
  int open_device();

  std::filesystem::path device_;
  int fd_ = -1;
};

enum class TmpChip { Tmp102, Tmp117 };

// "TMP102", "TMP117".
std::string to_string(TmpChip chip);

// The temperature register's two bytes (big-endian, as read) in °C. TMP102 (datasheet SBOS397,
// temperature register): normal mode is 12 bits left-justified, bit 0 of the second byte is 0;
// extended mode (EM=1 in the configuration register) is 13 bits with bit 0 set; either way two's
// complement at 0.0625 °C per LSB, and both are recognized by that bit. TMP117 (datasheet SNOSD82):
// 16-bit two's complement at 7.8125 m°C per LSB. Returns NaN for the TMP117's 0x8000, the reset
// value held until the first conversion completes.
double tmp_register_to_celsius(TmpChip chip, std::uint8_t msb, std::uint8_t lsb);

class I2cTmpSensor : public TemperatureSensor {
 public:
  // Throws core::InvalidInput when `bus` is null or the address is not a 7-bit address outside
  // the reserved ranges (0x08..0x77). Both chips answer at 0x48..0x4B by their ADD0 pin.
  I2cTmpSensor(std::unique_ptr<I2cBus> bus, int address, TmpChip chip,
               SensorClock clock = system_sensor_clock());

  // A bus error is ReadError with the errno text (a device that does not acknowledge gives
  // ENXIO or EREMOTEIO, depending on the adapter), except a bus device that does not exist
  // (ENOENT, ENODEV): Missing. TMP117 0x8000 (no conversion yet) is ReadError.
  TemperatureReading read() override;
  std::string describe() const override;

 private:
  std::unique_ptr<I2cBus> bus_;
  int address_;
  TmpChip chip_;
  SensorClock clock_;
};

}  // namespace tofcomp::hal
