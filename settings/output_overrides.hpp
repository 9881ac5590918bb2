// Where the daemon publishes, as its command line sets it over the configuration file:
// `--instance NAME` (the instance's socket and ring, ipc/instance_name.hpp), then `--socket PATH`
// and `--shm NAME`, which let a user without /run/tofcompd run a daemon of their own. The
// overrides hold across reloads: the file's outputs.socket.path and outputs.shm.name are
// replaced each time it is read.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "settings/daemon_config.hpp"

namespace tofcomp::settings {

struct OutputOverrides {
  std::optional<std::filesystem::path> socket_path;  // absolute
  std::optional<std::string> shm_name;
};

// From the command line's values, each empty when not given: the instance's names, replaced by
// `socket` (made absolute against the working directory) and `shm` when given. Throws
// DaemonConfigError naming the option whose value breaks the rules of outputs.socket.path,
// outputs.shm.name or an instance name.
OutputOverrides output_overrides(const std::string& instance, const std::string& socket,
                                 const std::string& shm);

// The configuration with the overrides in place of its socket path and ring name.
void apply_output_overrides(const OutputOverrides& overrides, DaemonConfig& config);

}  // namespace tofcomp::settings
