// tofcomp-ros2-bridge: tofcompd's compensated scans and the scanner's health to ROS 2 over DDS
// (docs/integration.md, "ROS 2").
//   tofcomp-ros2-bridge --config FILE [--check-config]
// Runs until SIGTERM or SIGINT. Exit status: 0 after a clean stop, or at once when the file says
// `enabled: false`; 1 when the configuration or DDS fails (the message says why); 2 for a bad
// command line.
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <iostream>
#include <string>

#include "bridges/ros2/bridge_config.hpp"
#include "bridges/ros2/bridge_loop.hpp"
#include "core/error.hpp"
#include "io/version.hpp"

namespace {

std::atomic<bool> stop_requested{false};

void request_stop(int) { stop_requested.store(true); }

}  // namespace

int main(int argc, char** argv) {
  using namespace tofcomp::bridges::ros2;
  CLI::App app("tofcomp-ros2-bridge: tofcompd's compensated scans and health to ROS 2 (DDS)");
  std::string config_file;
  bool check_only = false;
  app.add_option("-c,--config", config_file,
                 "Configuration file with a ros2: section (docs/integration.md)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_flag("--check-config", check_only, "Check the configuration file and exit");
  app.set_version_flag("--version", std::string("tofcomp-ros2-bridge ") + tofcomp::io::kVersion);
  CLI11_PARSE(app, argc, argv);

  try {
    const BridgeConfig config = load_bridge_config(config_file);
    if (check_only) {
      std::cout << config_file << ": ok\n";
      return 0;
    }
    if (!config.enabled) {
      std::cerr << "tofcomp-ros2-bridge: " << config_file
                << " says ros2.enabled: false; nothing to publish" << std::endl;
      return 0;
    }
    std::signal(SIGTERM, request_stop);
    std::signal(SIGINT, request_stop);
    run_bridge(config, stop_requested, std::cerr);
    return 0;
  } catch (const tofcomp::core::Error& e) {
    std::cerr << "tofcomp-ros2-bridge: " << e.what() << std::endl;
    return 1;
  }
}
