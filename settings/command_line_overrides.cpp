#include "settings/command_line_overrides.hpp"

#include "ipc/instance_name.hpp"
#include "settings/daemon_config_error.hpp"
#include "settings/log_settings.hpp"
#include "settings/output_checks.hpp"

namespace tofcomp::settings {

CommandLineOverrides command_line_overrides(const std::string& instance, const std::string& socket,
                                            const std::string& shm) {
  CommandLineOverrides overrides;
  if (!instance.empty()) {
    try {
      overrides.socket_path = ipc::instance_socket_path(instance);
      overrides.shm_name = ipc::instance_ring_name(instance);
    } catch (const core::InvalidInput& e) {
      throw DaemonConfigError(std::string("--instance: ") + e.what());
    }
  }
  if (!socket.empty()) {
    const std::filesystem::path path = std::filesystem::absolute(socket);
    if (const std::string problem = socket_path_problem(path); !problem.empty()) {
      throw DaemonConfigError("--socket " + socket + ": " + problem);
    }
    overrides.socket_path = path;
  }
  if (!shm.empty()) {
    if (const std::string problem = shm_name_problem(shm); !problem.empty()) {
      throw DaemonConfigError("--shm: " + problem);
    }
    overrides.shm_name = shm;
  }
  return overrides;
}

void add_log_overrides(bool to_stderr, const std::string& level, CommandLineOverrides& overrides) {
  if (to_stderr) overrides.log_target = LogTarget::Stderr;
  if (level.empty()) return;
  try {
    overrides.log_level = parse_log_level(level);
  } catch (const core::InvalidInput& e) {
    throw DaemonConfigError(std::string("--log-level: ") + e.what());
  }
}

void apply_command_line_overrides(const CommandLineOverrides& overrides, DaemonConfig& config) {
  if (overrides.socket_path) config.outputs.socket.path = *overrides.socket_path;
  if (overrides.shm_name) config.outputs.shm.name = *overrides.shm_name;
  if (overrides.log_target) config.log.target = *overrides.log_target;
  if (overrides.log_level) config.log.level = *overrides.log_level;
}

}  // namespace tofcomp::settings
