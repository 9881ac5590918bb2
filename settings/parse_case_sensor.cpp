// Readers of the `case_sensor` section (the case thermometer: one backend and its settings,
// plausibility limits) and the `power` section (the GPIO lines of the scanner's power).
#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <string>
#include <string_view>

#include "io/yaml_typed_fields.hpp"
#include "settings/section_parsers.hpp"

namespace tofcomp::settings::sections {

namespace {

using io::fields::between;
using io::fields::greater_than_up_to;

constexpr std::array<std::string_view, 4> kBackends = {"hwmon", "i2c", "w1", "simulated"};

// The sub-section of the chosen backend; the others' sub-sections must be absent.
void check_only_backend_section(const io::YamlMap& sensor, std::string_view backend) {
  for (const auto other : kBackends) {
    if (other != backend && sensor.has(other)) {
      sensor.fail(other, "applies to backend " + std::string(other) + " only; backend is " +
                             std::string(backend));
    }
  }
}

hal::HwmonSensorConfig parse_hwmon(const io::YamlMap& sensor, const ParseContext& context) {
  const auto map = io::fields::section(sensor, "hwmon", {"directory", "name", "channel", "root"});
  if (!map) sensor.fail("hwmon", "is missing: backend hwmon needs its directory or name");
  hal::HwmonSensorConfig out;
  if (map->has("directory") == map->has("name")) {
    throw io::YamlSchemaError(map->path() + " must give exactly one of directory and name");
  }
  out.directory = io::fields::path(*map, "directory", context.base_directory, {});
  out.name = io::fields::text(*map, "name", {});
  if (!out.directory.empty() && map->has("root")) {
    map->fail("root", "applies only with name (the directory is given)");
  }
  out.root = io::fields::path(*map, "root", context.base_directory, out.root);
  out.channel = static_cast<int>(io::fields::integer(*map, "channel", between(1, 999), out.channel));
  return out;
}

std::string hex_address(long address) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%02lx", static_cast<unsigned long>(address));
  return address < 0 ? std::to_string(address) : std::string(text);
}

hal::I2cSensorConfig parse_i2c(const io::YamlMap& sensor, const ParseContext& context) {
  hal::I2cSensorConfig out;
  const auto map = io::fields::section(sensor, "i2c", {"device", "address", "chip"});
  if (!map) return out;
  out.device = io::fields::path(*map, "device", context.base_directory, out.device);
  if (map->has("address")) {
    const long address = io::fields::whole_number(*map, "address");
    if (address < 0x08 || address > 0x77) {
      map->fail("address",
                "must be a 7-bit address between 0x08 and 0x77, not " + hex_address(address));
    }
    out.address = static_cast<int>(address);
  }
  out.chip = io::fields::choice<hal::TmpChip>(
      *map, "chip", {{"tmp102", hal::TmpChip::Tmp102}, {"tmp117", hal::TmpChip::Tmp117}}, out.chip);
  return out;
}

// "28-" and 12 hex digits: the DS18B20's family code and serial number.
bool is_ds18b20_id(std::string_view id) {
  if (id.size() != 15 || id.substr(0, 3) != "28-") return false;
  for (const char c : id.substr(3)) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

hal::W1SensorConfig parse_w1(const io::YamlMap& sensor, const ParseContext& context) {
  const auto map = io::fields::section(sensor, "w1", {"device_id", "root"});
  if (!map) sensor.fail("w1", "is missing: backend w1 needs its device_id");
  hal::W1SensorConfig out;
  out.device_id = map->text("device_id");
  if (!is_ds18b20_id(out.device_id)) {
    map->fail("device_id",
              "must be a DS18B20 id like \"28-0000075565b2\" (28- and 12 hex "
              "digits), not \"" +
                  out.device_id + "\"");
  }
  out.root = io::fields::path(*map, "root", context.base_directory, out.root);
  return out;
}

hal::SimulatedSensorConfig parse_simulated(const io::YamlMap& sensor) {
  hal::SimulatedSensorConfig out;
  if (const auto map = io::fields::section(sensor, "simulated", {"description"})) {
    out.description = io::fields::text(*map, "description", out.description);
  }
  return out;
}

void parse_limits(const io::YamlMap& map, hal::PlausibilityLimits& out) {
  out.min_c = io::fields::number(map, "min_c", between(-273.15, 1000), out.min_c);
  out.max_c = io::fields::number(map, "max_c", between(-273.15, 1000), out.max_c);
  out.max_rate_c_per_s =
      io::fields::number(map, "max_rate_c_per_s", greater_than_up_to(0, 1000), out.max_rate_c_per_s);
  out.jump_allowance_c =
      io::fields::number(map, "jump_allowance_c", between(0, 100), out.jump_allowance_c);
}

}  // namespace

void parse_case_sensor(const io::YamlMap& root, const ParseContext& context,
                       CaseSensorConfig& out) {
  // Required: a daemon must be told which thermometer it has.
  const auto section = io::fields::section(root, "case_sensor",
                                       {"backend", "hwmon", "i2c", "w1", "simulated",
                                        "poll_interval_ms", "stale_after_s", "limits"});
  if (!section) root.fail("case_sensor", "is missing");
  const io::YamlMap& sensor = *section;
  const std::string backend = sensor.text("backend");
  if (std::find(kBackends.begin(), kBackends.end(), backend) == kBackends.end()) {
    io::fields::fail_choice(sensor, "backend", backend, {kBackends.begin(), kBackends.end()});
  }
  check_only_backend_section(sensor, backend);
  if (backend == "hwmon") {
    out.sensor.backend = parse_hwmon(sensor, context);
  } else if (backend == "i2c") {
    out.sensor.backend = parse_i2c(sensor, context);
  } else if (backend == "w1") {
    out.sensor.backend = parse_w1(sensor, context);
  } else {
    out.sensor.backend = parse_simulated(sensor);
  }
  out.poll_interval =
      io::fields::milliseconds(sensor, "poll_interval_ms", between(10, 3600000), out.poll_interval);
  out.sensor.limits.max_age = std::chrono::duration<double>(io::fields::number(
      sensor, "stale_after_s", greater_than_up_to(0, 86400), out.sensor.limits.max_age.count()));
  if (const auto limits = io::fields::section(
          sensor, "limits", {"min_c", "max_c", "max_rate_c_per_s", "jump_allowance_c"})) {
    parse_limits(*limits, out.sensor.limits);
  }
}

namespace {

hal::GpioLineConfig parse_gpio_line(const io::YamlMap& map) {
  hal::GpioLineConfig out;
  out.chip = io::fields::required_text(map, "chip");
  out.line = io::fields::required_text(map, "line");
  out.active_low = map.boolean_or("active_low", out.active_low);
  return out;
}

}  // namespace

void parse_power(const io::YamlMap& root, PowerConfig& out) {
  const auto power = io::fields::section(root, "power", {"switch", "sense"});
  if (!power) return;
  if (const auto line = io::fields::section(*power, "switch", {"chip", "line", "active_low"})) {
    out.power_switch = parse_gpio_line(*line);
  }
  if (const auto line = io::fields::section(*power, "sense", {"chip", "line", "active_low"})) {
    out.sense = parse_gpio_line(*line);
  }
}

}  // namespace tofcomp::settings::sections
