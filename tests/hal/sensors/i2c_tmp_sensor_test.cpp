// I2cTmpSensor through a fake bus, with the datasheets' register examples as known answers
// (TMP102 SBOS397, TMP117 SNOSD82), and LinuxI2cBus on a bus that does not exist.
#include "hal/sensors/i2c_tmp_sensor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/error.hpp"

namespace tofcomp::hal {
namespace {

// What the fake bus saw, kept outside it since the sensor owns the bus.
struct BusLog {
  std::vector<int> addresses;
  std::vector<std::vector<std::uint8_t>> writes;
  std::vector<std::uint8_t> reply{0x00, 0x00};  // the bytes the next read returns
  std::optional<int> fail_with;                 // errno of a failing read
};

class FakeI2cBus : public I2cBus {
 public:
  explicit FakeI2cBus(BusLog& log) : log_(log) {}
  void set_address(int address) override { log_.addresses.push_back(address); }
  void write(std::span<const std::uint8_t> bytes) override {
    log_.writes.emplace_back(bytes.begin(), bytes.end());
  }
  void read(std::span<std::uint8_t> bytes) override {
    if (log_.fail_with) throw I2cError("fake bus: read failed", *log_.fail_with);
    ASSERT_EQ(bytes.size(), log_.reply.size());
    std::copy(log_.reply.begin(), log_.reply.end(), bytes.begin());
  }
  std::string describe() const override { return "/dev/i2c-fake"; }

 private:
  BusLog& log_;
};

TemperatureReading read_register(TmpChip chip, std::uint16_t value) {
  BusLog log;
  log.reply = {static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value & 0xff)};
  I2cTmpSensor sensor(std::make_unique<FakeI2cBus>(log), 0x48, chip);
  return sensor.read();
}

double celsius_of(TmpChip chip, std::uint16_t value) {
  const TemperatureReading reading = read_register(chip, value);
  EXPECT_TRUE(reading.valid()) << reading.detail;
  return reading.celsius;
}

TEST(I2cTmpSensor, AddressesTheChipAndReadsTheTemperatureRegister) {
  BusLog log;
  log.reply = {0x19, 0x00};
  I2cTmpSensor sensor(std::make_unique<FakeI2cBus>(log), 0x49, TmpChip::Tmp102);
  ASSERT_TRUE(sensor.read().valid());
  ASSERT_TRUE(sensor.read().valid());
  EXPECT_EQ(log.addresses, (std::vector<int>{0x49, 0x49}));
  const std::vector<std::uint8_t> pointer_to_temperature{0x00};
  EXPECT_EQ(log.writes, (std::vector<std::vector<std::uint8_t>>{pointer_to_temperature,
                                                                pointer_to_temperature}));
  EXPECT_NE(sensor.describe().find("TMP102 at 0x49"), std::string::npos) << sensor.describe();
}

TEST(I2cTmpSensor, Tmp102NormalModeDatasheetExamples) {
  // TMP102 datasheet, 12-bit temperature data format table.
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x7FF0), 127.9375);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x6400), 100.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x5000), 80.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x4B00), 75.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x3200), 50.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x1900), 25.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x0040), 0.25);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x0000), 0.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0xFFC0), -0.25);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0xE700), -25.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0xC900), -55.0);
}

TEST(I2cTmpSensor, Tmp102ExtendedModeDatasheetExamples) {
  // 13-bit format: the value shifted left by 3, bit 0 (EM) set.
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x4B01), 150.0);  // 0 1001 0110 0000
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x4001), 128.0);  // 0 1000 0000 0000
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0x0C81), 25.0);   // 0 0001 1001 0000
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0xFFE1), -0.25);  // 1 1111 1111 1100
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp102, 0xE481), -55.0);  // 1 1100 1001 0000
}

TEST(I2cTmpSensor, Tmp117DatasheetExamples) {
  // TMP117 datasheet, 16-bit temperature data format table (7.8125 m°C per LSB).
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp117, 0x0C80), 25.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp117, 0xF380), -25.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp117, 0x0001), 0.0078125);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp117, 0xFFFF), -0.0078125);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp117, 0x3200), 100.0);
  EXPECT_DOUBLE_EQ(celsius_of(TmpChip::Tmp117, 0xE480), -55.0);
}

TEST(I2cTmpSensor, Tmp117WithoutConversionIsReadError) {
  const TemperatureReading reading = read_register(TmpChip::Tmp117, 0x8000);
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_TRUE(std::isnan(reading.celsius));
  EXPECT_NE(reading.detail.find("0x8000"), std::string::npos) << reading.detail;
}

TEST(I2cTmpSensor, BusErrorsAreReadErrors) {
  for (const int error : {EIO, ENXIO, EREMOTEIO, ETIMEDOUT}) {
    BusLog log;
    log.fail_with = error;
    I2cTmpSensor sensor(std::make_unique<FakeI2cBus>(log), 0x48, TmpChip::Tmp117);
    const TemperatureReading reading = sensor.read();
    EXPECT_EQ(reading.validity, ReadingValidity::ReadError) << error;
    EXPECT_TRUE(std::isnan(reading.celsius));
    EXPECT_NE(reading.detail.find("read failed"), std::string::npos) << reading.detail;
    EXPECT_NE(reading.detail.find("TMP117 at 0x48"), std::string::npos) << reading.detail;
  }
}

TEST(I2cTmpSensor, RejectsBadAddresses) {
  BusLog log;
  for (const int address : {-1, 0x00, 0x07, 0x78, 0x7F, 0x148}) {
    EXPECT_THROW(I2cTmpSensor(std::make_unique<FakeI2cBus>(log), address, TmpChip::Tmp102),
                 core::InvalidInput)
        << address;
  }
  EXPECT_THROW(I2cTmpSensor(nullptr, 0x48, TmpChip::Tmp102), core::InvalidInput);
}

TEST(LinuxI2cBus, NonexistentBusIsAClearError) {
  const std::string path = "/dev/i2c-tofcomp-test-does-not-exist";
  LinuxI2cBus bus(path);
  try {
    bus.set_address(0x48);
    FAIL() << "no exception";
  } catch (const I2cError& error) {
    EXPECT_EQ(error.error_number(), ENOENT);
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }

  I2cTmpSensor sensor(std::make_unique<LinuxI2cBus>(path), 0x48, TmpChip::Tmp102);
  const TemperatureReading reading = sensor.read();
  EXPECT_EQ(reading.validity, ReadingValidity::Missing);
  EXPECT_TRUE(std::isnan(reading.celsius));
  EXPECT_NE(reading.detail.find(path), std::string::npos) << reading.detail;
}

}  // namespace
}  // namespace tofcomp::hal
