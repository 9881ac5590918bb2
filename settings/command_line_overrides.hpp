// What tofcompd's command line sets over the configuration file. Where it publishes:
// `--instance NAME` (the instance's socket and ring, ipc/instance_name.hpp), then `--socket PATH`
// and `--shm NAME`, which let several daemons of one user run side by side. How it logs: `-d`
// (log to stderr, as chronyd -d) and `--log-level LEVEL`. The overrides hold across reloads: the
// file's outputs.socket.path, outputs.shm.name, log.target and log.level are replaced each time
// it is read.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "settings/daemon_config.hpp"

namespace tofcomp::settings {

struct CommandLineOverrides {
  std::optional<std::filesystem::path> socket_path;  // absolute
  std::optional<std::string> shm_name;
  std::optional<LogTarget> log_target;
  std::optional<spdlog::level::level_enum> log_level;
};

// From the command line's values, each empty when not given: the instance's names, replaced by
// `socket` (made absolute against the working directory) and `shm` when given. Throws
// DaemonConfigError naming the option whose value breaks the rules of outputs.socket.path,
// outputs.shm.name or an instance name.
CommandLineOverrides command_line_overrides(const std::string& instance, const std::string& socket,
                                            const std::string& shm);

// Adds -d (`to_stderr`: log.target stderr) and --log-level (`level`, empty when not given; one of
// parse_log_level's names). Throws DaemonConfigError naming --log-level and the names accepted.
void add_log_overrides(bool to_stderr, const std::string& level, CommandLineOverrides& overrides);

// The configuration with the overrides in place of its values.
void apply_command_line_overrides(const CommandLineOverrides& overrides, DaemonConfig& config);

}  // namespace tofcomp::settings
