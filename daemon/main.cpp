// tofcompd: the temperature and mode-hopping compensation service for an LMS 200.
//   tofcompd [--config FILE] [--check-config] [--print-default-config]
// Without --config it runs on the built-in default (config/tofcompd.yaml): an emulated LMS 200
// and its simulated case sensor, with the bundled calibration. Exit status: 0 after a clean
// stop (SIGTERM, SIGINT), 1 when it cannot start (the message says why), 2 for a bad command
// line.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "daemon/daemon.hpp"
#include "daemon/service/logging.hpp"
#include "io/version.hpp"
#include "settings/daemon_config_yaml.hpp"
#include "settings/embedded_default_config.hpp"
#include "settings/pipeline_setup.hpp"

int main(int argc, char** argv) {
  using namespace tofcomp::daemon;
  CLI::App app("tofcompd: temperature and mode-hopping compensation of an LMS 200 (a service)");
  std::string config_file;
  bool check_only = false;
  bool print_default = false;
  app.add_option("-c,--config", config_file,
                 "Configuration file (docs/configuration.md); default: the built-in one, "
                 "an emulated LMS 200")
      ->check(CLI::ExistingFile);
  app.add_flag("--check-config", check_only, "Read and check the configuration, then exit");
  app.add_flag("--print-default-config", print_default,
               "Print the built-in configuration (a starting point) and exit");
  app.set_version_flag("--version", std::string("tofcompd ") + tofcomp::io::kVersion);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (print_default) {
    std::fwrite(tofcomp::settings::embedded_default_config_text().data(), 1,
                tofcomp::settings::embedded_default_config_text().size(), stdout);
    return 0;
  }
  bool logging = false;  // until then errors go to stderr alone
  try {
    const tofcomp::settings::DaemonConfig cfg =
        config_file.empty() ? tofcomp::settings::embedded_default_config()
                            : tofcomp::settings::load_daemon_config(config_file);
    if (check_only) {
      // The calibration it names, when it exists, as the pipeline would take it (an extension
      // included): a file the daemon would refuse fails the check.
      std::string calibration;
      if (!cfg.calibration.file.empty() && std::filesystem::exists(cfg.calibration.file)) {
        auto loaded = tofcomp::settings::read_configured_calibration(cfg);
        tofcomp::realtime::CompensationPipeline pipeline(tofcomp::settings::pipeline_settings(cfg));
        pipeline.set_calibration(loaded, 1);
        calibration = "; calibration " + cfg.calibration.file.string() +
                      (loaded->extension
                           ? " with the " + loaded->extension->name() +
                                 " extension"
                           : std::string());
      }
      std::printf("%s: valid%s\n", cfg.source.c_str(), calibration.c_str());
      return 0;
    }
    service::configure_logging(cfg.log.target, cfg.log.level);
    logging = true;
    spdlog::info("tofcompd {} starting with {}", tofcomp::io::kVersion, cfg.source);
    Daemon daemon(cfg, config_file);
    return daemon.run();
  } catch (const tofcomp::core::Error& e) {
    if (logging) {
      spdlog::critical("cannot start: {}", e.what());
    } else {
      std::fprintf(stderr, "tofcompd: %s\n", e.what());
    }
    return 1;
  } catch (const std::exception& e) {
    if (logging) {
      spdlog::critical("internal error: {}", e.what());
    } else {
      std::fprintf(stderr, "tofcompd: internal error: %s\n", e.what());
    }
    return 1;
  }
}
