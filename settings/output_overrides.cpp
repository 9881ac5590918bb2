#include "settings/output_overrides.hpp"

#include "ipc/instance_name.hpp"
#include "settings/daemon_config_error.hpp"
#include "settings/output_checks.hpp"

namespace tofcomp::settings {

OutputOverrides output_overrides(const std::string& instance, const std::string& socket,
                                 const std::string& shm) {
  OutputOverrides overrides;
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

void apply_output_overrides(const OutputOverrides& overrides, DaemonConfig& config) {
  if (overrides.socket_path) config.outputs.socket.path = *overrides.socket_path;
  if (overrides.shm_name) config.outputs.shm.name = *overrides.shm_name;
}

}  // namespace tofcomp::settings
