// W1Ds18b20Sensor against w1 device trees as the kernel's w1_therm lays them out. The backend
// trusts the kernel's crc verdict (YES/NO), so the CRC bytes in the lines below are not checked.
#include "hal/sensors/w1_ds18b20_sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "tests/hal/sensors/temporary_tree.hpp"

namespace tofcomp::hal {
namespace {

using testing::TemporaryTree;

constexpr const char* kDevice = "28-0000075565b2";

TemperatureReading read_slave(const std::string& content) {
  TemporaryTree tree;
  tree.write(std::string(kDevice) + "/w1_slave", content);
  return W1Ds18b20Sensor(kDevice, tree.root()).read();
}

TEST(W1Ds18b20Sensor, ReadsTheTemperature) {
  const TemperatureReading reading = read_slave(
      "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n"
      "72 01 4b 46 7f ff 0e 10 57 t=23125\n");
  ASSERT_TRUE(reading.valid()) << reading.detail;
  // Scratchpad 72 01: 0x0172 = 370 counts of 1/16 °C (datasheet) = 23.125 °C.
  EXPECT_DOUBLE_EQ(reading.celsius, 23.125);
}

TEST(W1Ds18b20Sensor, ReadsNegativeTemperatures) {
  // -10.125 °C is FF5Eh in the datasheet's format (-162 sixteenths).
  const TemperatureReading reading = read_slave(
      "5e ff 4b 46 7f ff 02 10 d8 : crc=d8 YES\n"
      "5e ff 4b 46 7f ff 02 10 d8 t=-10125\n");
  ASSERT_TRUE(reading.valid()) << reading.detail;
  EXPECT_DOUBLE_EQ(reading.celsius, -10.125);
}

TEST(W1Ds18b20Sensor, CrcMismatchIsReadError) {
  const TemperatureReading reading = read_slave(
      "72 01 4b 46 7f ff 0e 10 ff : crc=57 NO\n"
      "72 01 4b 46 7f ff 0e 10 ff t=23125\n");
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_TRUE(std::isnan(reading.celsius));
  EXPECT_NE(reading.detail.find("CRC"), std::string::npos) << reading.detail;
}

TEST(W1Ds18b20Sensor, PowerOnResetValueIsReadError) {
  // Datasheet: the temperature register powers up at +85 °C (0550h, scratchpad bytes 50 05).
  const TemperatureReading reading = read_slave(
      "50 05 4b 46 7f ff 0c 10 1c : crc=1c YES\n"
      "50 05 4b 46 7f ff 0c 10 1c t=85000\n");
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_TRUE(std::isnan(reading.celsius));
  EXPECT_NE(reading.detail.find("power-on reset value"), std::string::npos) << reading.detail;
}

TEST(W1Ds18b20Sensor, AllZeroScratchpadIsReadError) {
  // The Dallas CRC-8 of zeros is zero, so an absent device reads as a passing CRC.
  const TemperatureReading reading = read_slave(
      "00 00 00 00 00 00 00 00 00 : crc=00 YES\n"
      "00 00 00 00 00 00 00 00 00 t=0\n");
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_NE(reading.detail.find("all-zero"), std::string::npos) << reading.detail;
}

TEST(W1Ds18b20Sensor, MalformedContentIsReadErrorNamingIt) {
  for (const char* content : {
           "",
           "garbage\n",
           "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n",
           "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n72 01 4b 46 7f ff 0e 10 57\n",
           "72 01 4b 46 7f ff 0e 10 57 : crc=57 YES\n72 01 4b 46 7f ff 0e 10 57 t=2x\n",
           "72 01 4b 46 7f ff 0e 10 57 : crc=57 MAYBE\n72 01 4b 46 7f ff 0e 10 57 t=23125\n",
           "72 01 : crc=57 YES\n72 01 t=23125\n",
       }) {
    const TemperatureReading reading = read_slave(content);
    EXPECT_EQ(reading.validity, ReadingValidity::ReadError) << "content '" << content << "'";
    EXPECT_TRUE(std::isnan(reading.celsius));
    EXPECT_NE(reading.detail.find("malformed"), std::string::npos) << reading.detail;
  }
  const TemperatureReading reading = read_slave("garbage\n");
  EXPECT_NE(reading.detail.find("'garbage'"), std::string::npos) << reading.detail;
  EXPECT_NE(reading.detail.find("w1_slave"), std::string::npos) << reading.detail;
}

TEST(W1Ds18b20Sensor, MissingDeviceIsMissing) {
  TemporaryTree tree;
  tree.write("28-000000000001/w1_slave", "irrelevant\n");
  const TemperatureReading reading = W1Ds18b20Sensor(kDevice, tree.root()).read();
  EXPECT_EQ(reading.validity, ReadingValidity::Missing);
  EXPECT_TRUE(std::isnan(reading.celsius));
  EXPECT_NE(reading.detail.find(kDevice), std::string::npos) << reading.detail;
}

TEST(W1Ds18b20Sensor, RejectsDeviceIdsOfOtherForms) {
  for (const char* id : {"", "28-", "10-0000075565b2", "28-0000075565b", "28-0000075565bz",
                         "28-0000075565b2/..", "../28-0000075565b2"}) {
    EXPECT_THROW(W1Ds18b20Sensor{id}, core::InvalidInput) << id;
  }
  EXPECT_NO_THROW(W1Ds18b20Sensor{"28-0000075565B2"});
}

}  // namespace
}  // namespace tofcomp::hal
