// tofcomp-ros2-bridge: tofcompd's compensated scans and the scanner's health to ROS 2 over DDS
// (docs/integration.md, "ROS 2").
//   tofcomp-ros2-bridge --config FILE [--instance NAME] [--check-config]
// --instance NAME makes it tofcompd@NAME's bridge (tofcomp-ros2-bridge@NAME.service): that
// instance's socket unless the file names one, and a file naming another instance refused.
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
#include "io/help_format.hpp"
#include "io/version.hpp"
#include "ipc/instance_name.hpp"

namespace {

std::atomic<bool> stop_requested{false};

void request_stop(int) {
  stop_requested.store(true);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tofcomp::bridges::ros2;
  CLI::App app("tofcomp-ros2-bridge: tofcompd's compensated scans and health to ROS 2 (DDS)");
  tofcomp::io::use_gnu_help(app);
  std::string config_file;
  std::string instance;
  bool check_only = false;
  app.add_option("-c,--config", config_file,
                 "Configuration file with a ros2: section (docs/integration.md)")
      ->required()
      ->check(CLI::ExistingFile);
  // The daemon's own check of instance names (tofcompd --instance), so that every name tofcompd@
  // accepts is accepted here and nothing else.
  app.add_option("-i,--instance", instance,
                 "The tofcompd instance NAME: its socket /run/tofcompd/NAME/tofcompd.sock unless "
                 "the configuration names a socket; a configuration naming another instance is "
                 "refused")
      ->check([](const std::string& name) { return tofcomp::ipc::instance_name_problem(name); },
              "NAME");
  app.add_flag("--check-config", check_only, "Check the configuration file and exit");
  app.set_version_flag("--version", std::string("tofcomp-ros2-bridge ") + tofcomp::io::kVersion);
  // CLI11_PARSE would return CLI11's own codes (105, 106...); the documented status of a bad
  // command line is 2, as tofcomp-mqtt-bridge's.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  try {
    const BridgeConfig config = load_bridge_config(config_file, instance);
    if (check_only) {
      std::cout << config_file << ": ok; " << describe_bridge(config) << "\n";
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
