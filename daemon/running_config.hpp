// The configuration the daemon runs on (settings/daemon_config.hpp), and where a reload reads it
// from: a tofcompd.yaml, or the built-in default. Owns the running configuration and its file.
// A reload takes the new configuration's keys that can change while running; the keys that need
// a restart keep their running values until then.
#pragma once

#include <filesystem>
#include <string>

#include "settings/daemon_config.hpp"
#include "settings/command_line_overrides.hpp"

namespace tofcomp::daemon {

class RunningConfig {
 public:
  // file: where reloads read from; empty: the configuration is the built-in default and a
  // reload re-reads that. overrides: the command line's socket and ring, applied to every read.
  RunningConfig(settings::DaemonConfig config, std::filesystem::path file,
                settings::CommandLineOverrides overrides = {});

  const settings::DaemonConfig& current() const { return config_; }
  // What the daemon runs on, for its status: "built-in default" or the file's path.
  std::string name() const;
  // Where a reload reads from, for its messages: "the built-in default" or the file's path.
  std::string source() const;

  // Reads the configuration anew; throws as the reader does (core::Error naming the key).
  settings::DaemonConfig read() const;
  // Runs on `next`, but for the keys that need a restart (settings::keys_needing_restart).
  void apply(settings::DaemonConfig next);
  // A path a client gave, taken as the configuration's paths are: a relative one from the
  // configuration file's directory.
  std::filesystem::path resolve(std::filesystem::path path) const;

 private:
  settings::DaemonConfig config_;
  std::filesystem::path file_;
  settings::CommandLineOverrides overrides_;
};

}  // namespace tofcomp::daemon
