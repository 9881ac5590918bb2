#include "hal/sensors/i2c_tmp_sensor.hpp"

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "hal/sensors/sysfs_file.hpp"

namespace tofcomp::hal {
namespace {

std::string hex_address(int address) {
  std::array<char, 8> text{};
  std::snprintf(text.data(), text.size(), "0x%02x", static_cast<unsigned>(address) & 0xffu);
  return text.data();
}

// TMP117 temperature register reset value: no conversion has completed yet (TMP117 datasheet
// SNOSD82, temperature register).
constexpr std::uint16_t kTmp117NoConversion = 0x8000;

}  // namespace

I2cBus::~I2cBus() = default;

LinuxI2cBus::LinuxI2cBus(std::filesystem::path device) : device_(std::move(device)) {}

LinuxI2cBus::~LinuxI2cBus() {
  if (fd_ >= 0) ::close(fd_);
}

int LinuxI2cBus::open_device() {
  if (fd_ >= 0) return fd_;
  int fd = -1;
  do {
    fd = ::open(device_.c_str(), O_RDWR | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) {
    const int error = errno;
    throw I2cError("i2c bus " + device_.string() + ": cannot open: " + errno_text(error), error);
  }
  fd_ = fd;
  return fd_;
}

void LinuxI2cBus::set_address(int address) {
  const int fd = open_device();
  if (::ioctl(fd, I2C_SLAVE, static_cast<unsigned long>(address)) < 0) {
    const int error = errno;
    throw I2cError("i2c bus " + device_.string() + ": cannot select address " +
                       hex_address(address) + ": " + errno_text(error),
                   error);
  }
}

void LinuxI2cBus::write(std::span<const std::uint8_t> bytes) {
  const int fd = open_device();
  ssize_t n = -1;
  do {
    n = ::write(fd, bytes.data(), bytes.size());
  } while (n < 0 && errno == EINTR);
  if (n < 0) {
    const int error = errno;
    throw I2cError("i2c bus " + device_.string() + ": write failed: " + errno_text(error), error);
  }
  if (static_cast<std::size_t>(n) != bytes.size())
    throw I2cError("i2c bus " + device_.string() + ": short write of " + std::to_string(n) +
                       " of " + std::to_string(bytes.size()) + " bytes",
                   EIO);
}

void LinuxI2cBus::read(std::span<std::uint8_t> bytes) {
  const int fd = open_device();
  ssize_t n = -1;
  do {
    n = ::read(fd, bytes.data(), bytes.size());
  } while (n < 0 && errno == EINTR);
  if (n < 0) {
    const int error = errno;
    throw I2cError("i2c bus " + device_.string() + ": read failed: " + errno_text(error), error);
  }
  if (static_cast<std::size_t>(n) != bytes.size())
    throw I2cError("i2c bus " + device_.string() + ": short read of " + std::to_string(n) + " of " +
                       std::to_string(bytes.size()) + " bytes",
                   EIO);
}

std::string to_string(TmpChip chip) {
  switch (chip) {
    case TmpChip::Tmp102:
      return "TMP102";
    case TmpChip::Tmp117:
      return "TMP117";
  }
  return "unknown TMP chip";
}

double tmp_register_to_celsius(TmpChip chip, std::uint8_t msb, std::uint8_t lsb) {
  const auto raw = static_cast<std::uint16_t>((msb << 8) | lsb);
  const auto value = static_cast<std::int16_t>(raw);
  if (chip == TmpChip::Tmp117) {
    if (raw == kTmp117NoConversion) return std::numeric_limits<double>::quiet_NaN();
    return value * 7.8125e-3;
  }
  // TMP102: bit 0 set marks extended (13-bit) mode. >> of a negative value is arithmetic in
  // C++20, so the sign is kept.
  const bool extended = (raw & 0x0001u) != 0;
  const int counts = extended ? value >> 3 : value >> 4;
  return counts * 0.0625;
}

I2cTmpSensor::I2cTmpSensor(std::unique_ptr<I2cBus> bus, int address, TmpChip chip,
                           SensorClock clock)
    : bus_(std::move(bus)), address_(address), chip_(chip), clock_(std::move(clock)) {
  if (!bus_) throw core::InvalidInput(to_string(chip_) + " sensor: no i2c bus given");
  if (address_ < 0x08 || address_ > 0x77)
    throw core::InvalidInput(to_string(chip_) + " sensor on " + bus_->describe() + ": address " +
                             hex_address(address_) +
                             " is not a usable 7-bit i2c address (0x08..0x77)");
  if (!clock_) throw core::InvalidInput(describe() + ": no clock");
}

TemperatureReading I2cTmpSensor::read() {
  std::array<std::uint8_t, 2> bytes{};
  try {
    bus_->set_address(address_);
    const std::array<std::uint8_t, 1> temperature_pointer{0x00};
    bus_->write(temperature_pointer);
    bus_->read(bytes);
  } catch (const I2cError& error) {
    const int e = error.error_number();
    const auto validity =
        e == ENOENT || e == ENODEV ? ReadingValidity::Missing : ReadingValidity::ReadError;
    return invalid_reading(clock_(), validity, describe() + ": " + error.what());
  }
  const double celsius = tmp_register_to_celsius(chip_, bytes[0], bytes[1]);
  if (std::isnan(celsius))
    return invalid_reading(clock_(), ReadingValidity::ReadError,
                           describe() + ": temperature register 0x8000: no conversion yet");
  return valid_reading(clock_(), celsius);
}

std::string I2cTmpSensor::describe() const {
  return to_string(chip_) + " at " + hex_address(address_) + " on " + bus_->describe();
}

}  // namespace tofcomp::hal
