// tofcomp-mqtt-bridge: one tofcompd's telemetry to an MQTT broker (docs/integration.md, "Fleet
// telemetry over MQTT").
//   tofcomp-mqtt-bridge --config FILE [--instance NAME] [--check-config] [--verbose]
// Exit status: 0 after a clean stop (SIGTERM, SIGINT: "offline" published first), 1 when it
// cannot start (the message names the file and key at fault), 2 for a bad command line.
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <string>

#include "bridges/mqtt/bridge.hpp"
#include "bridges/mqtt/bridge_config.hpp"
#include "bridges/mqtt/password_file.hpp"
#include "bridges/mqtt/topics.hpp"
#include "core/error.hpp"
#include "io/help_format.hpp"
#include "io/version.hpp"
#include "ipc/instance_name.hpp"

namespace {

std::atomic<bool> g_stop{false};

extern "C" void request_stop(int) {
  g_stop = true;
}

void configure_logging(bool verbose) {
  auto logger = spdlog::stderr_logger_mt("tofcomp-mqtt-bridge");
  // Under systemd stderr goes to the journal, which stamps each line itself.
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %l %v");
  logger->set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_default_logger(logger);
}

std::string describe(const tofcomp::bridges::mqtt::BridgeConfig& config) {
  const tofcomp::bridges::mqtt::Topics topics(config);
  std::string out = config.source + ": valid; broker " + config.broker.host + ":" +
                    std::to_string(config.broker.port) + (config.broker.tls ? " (TLS)" : "") +
                    " as " + config.broker.client_id;
  if (config.broker.username) out += ", user " + *config.broker.username;
  out += "; topics " + topics.base + "/...; tofcompd " + config.tofcompd_socket +
         "; commands: reload " + (config.commands.reload ? "allowed" : "refused") +
         ", recalibrate " + (config.commands.recalibrate ? "allowed" : "refused");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tofcomp::bridges::mqtt;
  CLI::App app(
      "tofcomp-mqtt-bridge: one tofcompd's status, calibration, junction temperature, "
      "diagnosis and range summary to an MQTT broker");
  tofcomp::io::use_gnu_help(app);
  std::string config_file;
  std::string instance;
  bool check_only = false;
  bool verbose = false;
  app.add_option("-c,--config", config_file, "Configuration file (docs/integration.md)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-i,--instance", instance,
                 "The tofcompd instance NAME: its socket /run/tofcompd/NAME/tofcompd.sock and "
                 "the topics' instance level, unless the configuration says otherwise")
      ->check([](const std::string& name) { return tofcomp::ipc::instance_name_problem(name); },
              "NAME");
  app.add_flag("--check-config", check_only, "Read and check the configuration, then exit");
  app.add_flag("-v,--verbose", verbose, "Log libmosquitto's traffic too (debug level)");
  app.set_version_flag("--version", std::string("tofcomp-mqtt-bridge ") + tofcomp::io::kVersion);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  configure_logging(verbose);
  try {
    BridgeConfig config = read_bridge_config(config_file, instance);
    const std::string password =
        config.broker.password_file ? read_password_file(*config.broker.password_file) : "";
    if (check_only) {
      std::printf("%s\n", describe(config).c_str());
      return 0;
    }
    std::signal(SIGTERM, request_stop);
    std::signal(SIGINT, request_stop);
    std::signal(SIGPIPE, SIG_IGN);
    Bridge bridge(std::move(config), password);
    bridge.run(g_stop);
    return 0;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
