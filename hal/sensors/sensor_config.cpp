#include "hal/sensors/sensor_config.hpp"

#include <type_traits>
#include <utility>

#include "core/error.hpp"
#include "hal/sensors/hwmon_sensor.hpp"
#include "hal/sensors/simulated_sensor.hpp"
#include "hal/sensors/w1_ds18b20_sensor.hpp"

namespace tofcomp::hal {
namespace {

std::unique_ptr<TemperatureSensor> make_backend(const HwmonSensorConfig& config,
                                                const std::function<double()>&,
                                                const SensorClock& clock) {
  const bool has_directory = !config.directory.empty();
  const bool has_name = !config.name.empty();
  if (has_directory == has_name)
    throw core::InvalidInput(
        "sensor config: hwmon: give exactly one of directory and name (directory '" +
        config.directory.string() + "', name '" + config.name + "')");
  if (has_directory) return std::make_unique<HwmonSensor>(config.directory, config.channel, clock);
  return std::make_unique<HwmonSensor>(
      HwmonSensor::by_name(config.name, config.channel, config.root, clock));
}

std::unique_ptr<TemperatureSensor> make_backend(const I2cSensorConfig& config,
                                                const std::function<double()>&,
                                                const SensorClock& clock) {
  if (config.device.empty()) throw core::InvalidInput("sensor config: i2c: empty device path");
  return std::make_unique<I2cTmpSensor>(std::make_unique<LinuxI2cBus>(config.device),
                                        config.address, config.chip, clock);
}

std::unique_ptr<TemperatureSensor> make_backend(const W1SensorConfig& config,
                                                const std::function<double()>&,
                                                const SensorClock& clock) {
  return std::make_unique<W1Ds18b20Sensor>(config.device_id, config.root, clock);
}

std::unique_ptr<TemperatureSensor> make_backend(const SimulatedSensorConfig& config,
                                                const std::function<double()>& source,
                                                const SensorClock& clock) {
  if (!source)
    throw core::InvalidInput("sensor config: simulated sensor '" + config.description +
                             "': no temperature source connected");
  return std::make_unique<SimulatedSensor>(source, config.description, clock);
}

}  // namespace

std::unique_ptr<TemperatureSensor> make_temperature_sensor(const SensorConfig& config,
                                                           std::function<double()> simulated_source,
                                                           SensorClock clock) {
  if (!clock) throw core::InvalidInput("sensor config: no clock");
  auto backend = std::visit(
      [&](const auto& backend_config) {
        return make_backend(backend_config, simulated_source, clock);
      },
      config.backend);
  return std::make_unique<CheckedSensor>(std::move(backend), config.limits, std::move(clock));
}

}  // namespace tofcomp::hal
