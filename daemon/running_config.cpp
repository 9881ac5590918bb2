#include "daemon/running_config.hpp"

#include <utility>

#include "settings/daemon_config_yaml.hpp"
#include "settings/embedded_default_config.hpp"

namespace tofcomp::daemon {

RunningConfig::RunningConfig(settings::DaemonConfig config, std::filesystem::path file,
                             settings::CommandLineOverrides overrides)
    : config_(std::move(config)), file_(std::move(file)), overrides_(std::move(overrides)) {}

std::string RunningConfig::name() const {
  return file_.empty() ? "built-in default" : file_.string();
}

std::string RunningConfig::source() const {
  return file_.empty() ? "the built-in default" : file_.string();
}

settings::DaemonConfig RunningConfig::read() const {
  settings::DaemonConfig config = file_.empty() ? settings::embedded_default_config()
                                                : settings::load_daemon_config(file_);
  settings::apply_command_line_overrides(overrides_, config);
  return config;
}

void RunningConfig::apply(settings::DaemonConfig next) {
  next.link = config_.link;
  next.emulator = config_.emulator;
  next.case_sensor = config_.case_sensor;
  next.power = config_.power;
  next.outputs = config_.outputs;
  config_ = std::move(next);
}

std::filesystem::path RunningConfig::resolve(std::filesystem::path path) const {
  if (path.is_relative() && !file_.empty()) return file_.parent_path() / path;
  return path;
}

}  // namespace tofcomp::daemon
