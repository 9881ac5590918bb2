#include "hal/sensors/hwmon_sensor.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <system_error>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "hal/sensors/sysfs_file.hpp"

namespace tofcomp::hal {
namespace {

void check_channel(int channel, const std::string& where) {
  if (channel < 1)
    throw core::InvalidInput("hwmon sensor " + where + ": channel must be 1 or more, got " +
                             std::to_string(channel));
}

// The directories under `root` whose `name` file reads `name`, in sorted order.
std::vector<std::filesystem::path> find_by_name(const std::filesystem::path& root,
                                                const std::string& name, std::error_code& error) {
  std::vector<std::filesystem::path> found;
  std::filesystem::directory_iterator it(root, error);
  if (error) return found;
  for (; it != std::filesystem::directory_iterator(); it.increment(error)) {
    const SysfsRead name_file = read_sysfs_file(it->path() / "name");
    if (name_file.error == 0 && trim(name_file.content) == name) found.push_back(it->path());
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

HwmonSensor::HwmonSensor(std::filesystem::path device_dir, int channel, SensorClock clock)
    : HwmonSensor(std::move(device_dir), {}, {}, channel, std::move(clock)) {}

HwmonSensor HwmonSensor::by_name(std::string name, int channel, std::filesystem::path root,
                                 SensorClock clock) {
  if (name.empty()) throw core::InvalidInput("hwmon sensor: empty device name");
  if (root.empty()) throw core::InvalidInput("hwmon sensor '" + name + "': empty root directory");
  return HwmonSensor({}, std::move(name), std::move(root), channel, std::move(clock));
}

HwmonSensor::HwmonSensor(std::filesystem::path device_dir, std::string name,
                         std::filesystem::path root, int channel, SensorClock clock)
    : device_dir_(std::move(device_dir)),
      name_(std::move(name)),
      root_(std::move(root)),
      channel_(channel),
      clock_(std::move(clock)) {
  if (name_.empty() && device_dir_.empty())
    throw core::InvalidInput("hwmon sensor: empty device directory");
  check_channel(channel_, describe());
  if (!clock_) throw core::InvalidInput("hwmon sensor " + describe() + ": no clock");
}

TemperatureReading HwmonSensor::read() {
  std::filesystem::path dir = device_dir_;
  if (!name_.empty()) {
    std::error_code error;
    const auto found = find_by_name(root_, name_, error);
    if (error)
      return invalid_reading(clock_(), validity_of_errno(error.value()),
                             "hwmon root " + root_.string() + ": " + error.message());
    if (found.empty())
      return invalid_reading(clock_(), ReadingValidity::Missing,
                             "no hwmon device named '" + name_ + "' under " + root_.string());
    if (found.size() > 1) {
      std::string list;
      for (const auto& path : found) list += (list.empty() ? "" : ", ") + path.string();
      return invalid_reading(clock_(), ReadingValidity::ReadError,
                             std::to_string(found.size()) + " hwmon devices named '" + name_ +
                                 "' (" + list + "); configure the directory instead");
    }
    dir = found.front();
  }

  const auto file = dir / ("temp" + std::to_string(channel_) + "_input");
  const SysfsRead input = read_sysfs_file(file);
  if (input.error != 0) {
    std::string detail = file.string() + ": " + errno_text(input.error);
    if (input.error == ENOENT && !std::filesystem::is_directory(dir))
      detail = "no hwmon device directory " + dir.string();
    return invalid_reading(clock_(), validity_of_errno(input.error), detail);
  }

  const std::string_view text = trim(input.content);
  std::int64_t millidegrees = 0;
  const auto [end, parse_error] =
      std::from_chars(text.data(), text.data() + text.size(), millidegrees);
  if (text.empty() || parse_error != std::errc() || end != text.data() + text.size())
    return invalid_reading(
        clock_(), ReadingValidity::ReadError,
        file.string() + ": not a millidegree value: '" + std::string(text) + "'");
  return valid_reading(clock_(), static_cast<double>(millidegrees) / 1000.0);
}

std::string HwmonSensor::describe() const {
  const std::string channel = " temp" + std::to_string(channel_);
  if (!name_.empty()) return "hwmon '" + name_ + "' under " + root_.string() + channel;
  return "hwmon " + device_dir_.string() + channel;
}

}  // namespace tofcomp::hal
