// HwmonSensor against hwmon trees laid out as the kernel does (Documentation/hwmon/
// sysfs-interface: tempN_input in millidegrees Celsius, a `name` file per device).
#include "hal/sensors/hwmon_sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/error.hpp"
#include "tests/hal/sensors/temporary_tree.hpp"

namespace tofcomp::hal {
namespace {

using testing::TemporaryTree;

TEST(HwmonSensor, ReadsMillidegreesOfTheChannel) {
  TemporaryTree tree;
  tree.write("hwmon2/name", "lm75\n");
  tree.write("hwmon2/temp1_input", "23125\n");
  tree.write("hwmon2/temp2_input", "41500\n");

  HwmonSensor channel1(tree.root() / "hwmon2", 1);
  const TemperatureReading reading = channel1.read();
  ASSERT_TRUE(reading.valid()) << reading.detail;
  EXPECT_DOUBLE_EQ(reading.celsius, 23.125);
  EXPECT_TRUE(reading.detail.empty());

  HwmonSensor channel2(tree.root() / "hwmon2", 2);
  EXPECT_DOUBLE_EQ(channel2.read().celsius, 41.5);
}

TEST(HwmonSensor, ReadsNegativeTemperatures) {
  TemporaryTree tree;
  tree.write("hwmon0/temp1_input", "-10125\n");
  const TemperatureReading reading = HwmonSensor(tree.root() / "hwmon0", 1).read();
  ASSERT_TRUE(reading.valid()) << reading.detail;
  EXPECT_DOUBLE_EQ(reading.celsius, -10.125);
}

TEST(HwmonSensor, FindsTheDeviceByName) {
  TemporaryTree tree;
  tree.write("hwmon0/name", "acpitz\n");
  tree.write("hwmon0/temp1_input", "50000\n");
  tree.write("hwmon3/name", "tmp102\n");
  tree.write("hwmon3/temp1_input", "-5250\n");

  HwmonSensor sensor = HwmonSensor::by_name("tmp102", 1, tree.root());
  const TemperatureReading reading = sensor.read();
  ASSERT_TRUE(reading.valid()) << reading.detail;
  EXPECT_DOUBLE_EQ(reading.celsius, -5.25);
  EXPECT_NE(sensor.describe().find("tmp102"), std::string::npos);
}

TEST(HwmonSensor, NameNotFoundIsMissing) {
  TemporaryTree tree;
  tree.write("hwmon0/name", "acpitz\n");
  tree.write("hwmon0/temp1_input", "50000\n");
  const TemperatureReading reading = HwmonSensor::by_name("lm75", 1, tree.root()).read();
  EXPECT_EQ(reading.validity, ReadingValidity::Missing);
  EXPECT_TRUE(std::isnan(reading.celsius));
  EXPECT_NE(reading.detail.find("lm75"), std::string::npos) << reading.detail;
}

TEST(HwmonSensor, AmbiguousNameIsReadError) {
  TemporaryTree tree;
  tree.write("hwmon1/name", "tmp102\n");
  tree.write("hwmon1/temp1_input", "20000\n");
  tree.write("hwmon2/name", "tmp102\n");
  tree.write("hwmon2/temp1_input", "21000\n");
  const TemperatureReading reading = HwmonSensor::by_name("tmp102", 1, tree.root()).read();
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_NE(reading.detail.find("hwmon1"), std::string::npos) << reading.detail;
  EXPECT_NE(reading.detail.find("hwmon2"), std::string::npos) << reading.detail;
}

TEST(HwmonSensor, MissingDirectoryOrChannelIsMissing) {
  TemporaryTree tree;
  tree.write("hwmon0/temp1_input", "20000\n");

  const TemperatureReading no_device = HwmonSensor(tree.root() / "hwmon7", 1).read();
  EXPECT_EQ(no_device.validity, ReadingValidity::Missing);
  EXPECT_TRUE(std::isnan(no_device.celsius));
  EXPECT_NE(no_device.detail.find("hwmon7"), std::string::npos) << no_device.detail;

  const TemperatureReading no_channel = HwmonSensor(tree.root() / "hwmon0", 3).read();
  EXPECT_EQ(no_channel.validity, ReadingValidity::Missing);
  EXPECT_NE(no_channel.detail.find("temp3_input"), std::string::npos) << no_channel.detail;
}

TEST(HwmonSensor, UnparsableContentIsReadErrorNamingIt) {
  TemporaryTree tree;
  for (const char* content : {"", "\n", "abc\n", "23.5\n", "23125 x\n"}) {
    tree.write("hwmon0/temp1_input", content);
    const TemperatureReading reading = HwmonSensor(tree.root() / "hwmon0", 1).read();
    EXPECT_EQ(reading.validity, ReadingValidity::ReadError) << "content '" << content << "'";
    EXPECT_TRUE(std::isnan(reading.celsius));
    EXPECT_NE(reading.detail.find("temp1_input"), std::string::npos) << reading.detail;
  }
  tree.write("hwmon0/temp1_input", "abc\n");
  const TemperatureReading reading = HwmonSensor(tree.root() / "hwmon0", 1).read();
  EXPECT_NE(reading.detail.find("'abc'"), std::string::npos) << reading.detail;
}

TEST(HwmonSensor, FailedReadIsReadErrorWithTheSystemError) {
  // A directory in place of the attribute opens but fails to read (EISDIR), as a driver that
  // cannot reach its chip fails with EIO or ENODATA.
  TemporaryTree tree;
  std::filesystem::create_directories(tree.root() / "hwmon0" / "temp1_input");
  const TemperatureReading reading = HwmonSensor(tree.root() / "hwmon0", 1).read();
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_NE(reading.detail.find("Is a directory"), std::string::npos) << reading.detail;
}

TEST(HwmonSensor, RejectsBadConfiguration) {
  EXPECT_THROW(HwmonSensor("/sys/class/hwmon/hwmon0", 0), core::InvalidInput);
  EXPECT_THROW(HwmonSensor("", 1), core::InvalidInput);
  EXPECT_THROW(HwmonSensor::by_name("", 1), core::InvalidInput);
  try {
    HwmonSensor::by_name("lm75", -1);
    FAIL() << "no exception";
  } catch (const core::InvalidInput& error) {
    EXPECT_NE(std::string(error.what()).find("lm75"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("channel"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace tofcomp::hal
