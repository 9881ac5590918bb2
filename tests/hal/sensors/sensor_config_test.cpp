// make_temperature_sensor: each backend built from its config, inside the plausibility checks;
// SimulatedSensor.
#include "hal/sensors/sensor_config.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "hal/sensors/simulated_sensor.hpp"
#include "tests/hal/sensors/temporary_tree.hpp"

namespace tofcomp::hal {
namespace {

using testing::TemporaryTree;

TEST(SimulatedSensor, ReturnsTheSourceAsValid) {
  double value = 31.25;
  SimulatedSensor sensor([&] { return value; }, "twin case");
  EXPECT_EQ(sensor.read().celsius, 31.25);
  value = -3.5;
  const TemperatureReading reading = sensor.read();
  ASSERT_TRUE(reading.valid());
  EXPECT_EQ(reading.celsius, -3.5);
  EXPECT_EQ(sensor.describe(), "twin case");
}

TEST(SimulatedSensor, NonFiniteOrThrowingSourceIsReadError) {
  SimulatedSensor nan_source([] { return NAN; }, "twin case");
  EXPECT_EQ(nan_source.read().validity, ReadingValidity::ReadError);
  SimulatedSensor throwing([]() -> double { throw std::runtime_error("twin stopped"); }, "twin");
  const TemperatureReading reading = throwing.read();
  EXPECT_EQ(reading.validity, ReadingValidity::ReadError);
  EXPECT_NE(reading.detail.find("twin stopped"), std::string::npos) << reading.detail;
  EXPECT_THROW(SimulatedSensor({}, "twin"), core::InvalidInput);
}

TEST(SensorConfig, BuildsTheSimulatedBackendInsideThePlausibilityChecks) {
  SensorConfig config;  // simulated by default
  config.limits.max_c = 60.0;
  double value = 40.0;
  auto sensor = make_temperature_sensor(config, [&] { return value; });
  EXPECT_TRUE(sensor->read().valid());
  value = 61.0;
  EXPECT_EQ(sensor->read().validity, ReadingValidity::Implausible);
  EXPECT_THROW(make_temperature_sensor(config, {}), core::InvalidInput);
}

TEST(SensorConfig, BuildsHwmonByDirectoryOrName) {
  TemporaryTree tree;
  tree.write("hwmon1/name", "lm75\n");
  tree.write("hwmon1/temp1_input", "36500\n");

  SensorConfig by_directory;
  by_directory.backend = HwmonSensorConfig{tree.root() / "hwmon1", "", 1, tree.root()};
  EXPECT_DOUBLE_EQ(make_temperature_sensor(by_directory, {})->read().celsius, 36.5);

  SensorConfig by_name;
  by_name.backend = HwmonSensorConfig{"", "lm75", 1, tree.root()};
  EXPECT_DOUBLE_EQ(make_temperature_sensor(by_name, {})->read().celsius, 36.5);

  SensorConfig both;
  both.backend = HwmonSensorConfig{tree.root() / "hwmon1", "lm75", 1, tree.root()};
  EXPECT_THROW(make_temperature_sensor(both, {}), core::InvalidInput);
  SensorConfig neither;
  neither.backend = HwmonSensorConfig{};
  EXPECT_THROW(make_temperature_sensor(neither, {}), core::InvalidInput);
}

TEST(SensorConfig, BuildsW1AndI2cWithoutOpeningAnything) {
  TemporaryTree tree;
  SensorConfig w1;
  w1.backend = W1SensorConfig{"28-0000075565b2", tree.root()};
  EXPECT_EQ(make_temperature_sensor(w1, {})->read().validity, ReadingValidity::Missing);

  SensorConfig i2c;
  i2c.backend = I2cSensorConfig{tree.root() / "i2c-9", 0x48, TmpChip::Tmp117};
  auto sensor = make_temperature_sensor(i2c, {});
  EXPECT_EQ(sensor->read().validity, ReadingValidity::Missing);
  EXPECT_NE(sensor->describe().find("TMP117 at 0x48"), std::string::npos) << sensor->describe();

  SensorConfig bad_address;
  bad_address.backend = I2cSensorConfig{"/dev/i2c-1", 0x80, TmpChip::Tmp102};
  EXPECT_THROW(make_temperature_sensor(bad_address, {}), core::InvalidInput);
  SensorConfig bad_id;
  bad_id.backend = W1SensorConfig{"10-0000075565b2", tree.root()};
  EXPECT_THROW(make_temperature_sensor(bad_id, {}), core::InvalidInput);
  SensorConfig bad_limits;
  bad_limits.limits.min_c = 200.0;
  EXPECT_THROW(make_temperature_sensor(bad_limits, [] { return 20.0; }), core::InvalidInput);
}

}  // namespace
}  // namespace tofcomp::hal
