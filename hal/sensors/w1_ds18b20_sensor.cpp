#include "hal/sensors/w1_ds18b20_sensor.hpp"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <utility>

#include "core/error.hpp"
#include "hal/sensors/sysfs_file.hpp"

namespace tofcomp::hal {
namespace {

bool is_hex(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

// True when `text` starts with nine two-digit hex bytes separated by single blanks; `all_zero`
// tells whether they are all 00.
bool scratchpad_bytes(std::string_view text, bool& all_zero) {
  constexpr std::size_t kBytes = 9;
  if (text.size() < kBytes * 3 - 1) return false;
  all_zero = true;
  for (std::size_t i = 0; i < kBytes; ++i) {
    const char hi = text[3 * i];
    const char lo = text[3 * i + 1];
    if (!is_hex(hi) || !is_hex(lo)) return false;
    if (i + 1 < kBytes && text[3 * i + 2] != ' ') return false;
    if (hi != '0' || lo != '0') all_zero = false;
  }
  return true;
}

// Millidegrees of the DS18B20 power-on reset value +85 °C (datasheet: scratchpad bytes 0-1
// read 50h 05h until the first conversion).
constexpr std::int64_t kPowerOnResetMillidegrees = 85000;

}  // namespace

TemperatureReading parse_w1_slave(std::string_view content, const std::string& where,
                                  std::chrono::system_clock::time_point time) {
  const auto malformed = [&](const std::string& why) {
    return invalid_reading(
        time, ReadingValidity::ReadError,
        where + ": malformed w1_slave content (" + why + "): '" + std::string(trim(content)) + "'");
  };
  const auto line_end = content.find('\n');
  if (line_end == std::string_view::npos) return malformed("expected two lines");
  const std::string_view crc_line = trim(content.substr(0, line_end));
  const std::string_view data_line = trim(content.substr(line_end + 1));
  if (data_line.empty()) return malformed("expected two lines");

  bool all_zero = false;
  if (!scratchpad_bytes(crc_line, all_zero)) return malformed("no scratchpad bytes");
  const auto crc_at = crc_line.find(": crc=");
  if (crc_at == std::string_view::npos) return malformed("no crc verdict");
  const std::string_view verdict = crc_line.substr(crc_line.rfind(' ') + 1);
  if (verdict == "NO")
    return invalid_reading(
        time, ReadingValidity::ReadError,
        where + ": CRC mismatch (" + std::string(crc_line.substr(crc_at + 2)) + ")");
  if (verdict != "YES") return malformed("crc verdict is neither YES nor NO");
  if (all_zero)
    return invalid_reading(time, ReadingValidity::ReadError,
                           where + ": all-zero scratchpad (device not answering)");

  const auto t_at = data_line.find("t=");
  if (t_at == std::string_view::npos) return malformed("no t= value");
  const std::string_view value = data_line.substr(t_at + 2);
  std::int64_t millidegrees = 0;
  const auto [end, error] =
      std::from_chars(value.data(), value.data() + value.size(), millidegrees);
  if (value.empty() || error != std::errc() || end != value.data() + value.size())
    return malformed("t= is not an integer");
  if (millidegrees == kPowerOnResetMillidegrees)
    return invalid_reading(time, ReadingValidity::ReadError,
                           where +
                               ": power-on reset value 85.0 °C (scratchpad 50 05): no "
                               "conversion took place");
  return valid_reading(time, static_cast<double>(millidegrees) / 1000.0);
}

W1Ds18b20Sensor::W1Ds18b20Sensor(std::string device_id, std::filesystem::path root,
                                 SensorClock clock)
    : device_id_(std::move(device_id)), root_(std::move(root)), clock_(std::move(clock)) {
  bool well_formed = device_id_.size() == 15 && device_id_.rfind("28-", 0) == 0;
  for (std::size_t i = 3; well_formed && i < device_id_.size(); ++i)
    well_formed = is_hex(device_id_[i]);
  if (!well_formed)
    throw core::InvalidInput("DS18B20 sensor: device id '" + device_id_ +
                             "' is not of the form 28-xxxxxxxxxxxx (family 28, 12 hex digits)");
  if (root_.empty())
    throw core::InvalidInput("DS18B20 sensor " + device_id_ + ": empty w1 devices directory");
  if (!clock_) throw core::InvalidInput("DS18B20 sensor " + device_id_ + ": no clock");
}

TemperatureReading W1Ds18b20Sensor::read() {
  const auto file = root_ / device_id_ / "w1_slave";
  const SysfsRead slave = read_sysfs_file(file);
  if (slave.error != 0) {
    if (slave.error == ENOENT)
      return invalid_reading(clock_(), ReadingValidity::Missing,
                             "no 1-Wire device " + device_id_ + " (" + file.string() + ")");
    return invalid_reading(clock_(), validity_of_errno(slave.error),
                           file.string() + ": " + errno_text(slave.error));
  }
  return parse_w1_slave(slave.content, file.string(), clock_());
}

std::string W1Ds18b20Sensor::describe() const {
  return "DS18B20 " + device_id_ + " under " + root_.string();
}

}  // namespace tofcomp::hal
