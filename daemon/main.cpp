// tofcompd: the temperature and mode-hopping compensation service for an LMS 200.
//   tofcompd [--config FILE] [--instance NAME] [--socket PATH] [--shm NAME] [-d]
//            [--log-level LEVEL] [--check-config] [--print-default-config]
// Without --config it runs on the built-in default (config/tofcompd.yaml): an emulated LMS 200
// and its simulated case sensor, with the bundled calibration. Where it publishes, unless the
// configuration says, is the system's as root and the user's own otherwise
// (ipc/default_places.hpp); --instance, --socket and --shm replace it
// (settings/command_line_overrides.hpp). Exit status: 0 after a clean
// stop (SIGTERM, SIGINT), 1 when it cannot start (the message says why), 2 for a bad command
// line.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "daemon/config_check.hpp"
#include "daemon/daemon.hpp"
#include "daemon/private_directory.hpp"
#include "daemon/service/logging.hpp"
#include "daemon/training_child.hpp"
#include "io/help_format.hpp"
#include "io/version.hpp"
#include "ipc/default_places.hpp"
#include "ipc/instance_name.hpp"
#include "settings/command_line_overrides.hpp"
#include "settings/daemon_config_yaml.hpp"
#include "settings/embedded_default_config.hpp"
#include "settings/log_settings.hpp"

int main(int argc, char** argv) {
  using namespace tofcomp::daemon;
  // The daemon's own training process (daemon/training_child.hpp), never started by hand.
  if (argc > 1 && std::string(argv[1]) == kTrainWorkerFlag) return training_child_main(argc, argv);
  CLI::App app("tofcompd: temperature and mode-hopping compensation of an LMS 200 (a service)");
  tofcomp::io::use_gnu_help(app);
  std::string config_file;
  std::string instance;
  std::string socket_path;
  std::string shm_name;
  bool log_to_stderr = false;
  std::string log_level;
  bool check_only = false;
  bool print_default = false;
  app.add_option("-c,--config", config_file,
                 "Configuration file (docs/configuration.md); default: the built-in one, "
                 "an emulated LMS 200")
      ->check(CLI::ExistingFile);
  app.add_option("-i,--instance", instance,
                 "Run as instance NAME: socket /run/tofcompd/NAME/tofcompd.sock, ring "
                 "/tofcompd-NAME, log identity tofcompd@NAME (tofcompd@.service)")
      ->check([](const std::string& name) { return tofcomp::ipc::instance_name_problem(name); },
              "NAME");
  app.add_option("--socket", socket_path,
                 "Serve the Unix socket at PATH instead of outputs.socket.path (or the instance's)")
      ->type_name("PATH");
  app.add_option("--shm", shm_name,
                 "Publish the ring under this shared-memory name (/NAME) instead of "
                 "outputs.shm.name (or the instance's)")
      ->type_name("NAME");
  app.add_flag("-d,--stderr", log_to_stderr,
               "Log to stderr (log.target: stderr), whatever the configuration says; tofcompd "
               "never forks, so it is in the foreground either way");
  app.add_option("--log-level", log_level,
                 "Log at LEVEL (log.level): trace, debug, info, warn, error, critical or off")
      ->type_name("LEVEL")
      ->check(
          [](const std::string& level) {
            try {
              tofcomp::settings::parse_log_level(level);
              return std::string();
            } catch (const tofcomp::core::InvalidInput& e) {
              return std::string(e.what());
            }
          },
          "LEVEL");
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
    tofcomp::settings::CommandLineOverrides overrides =
        tofcomp::settings::command_line_overrides(instance, socket_path, shm_name);
    tofcomp::settings::add_log_overrides(log_to_stderr, log_level, overrides);
    const tofcomp::ipc::DaemonPlaces places = tofcomp::settings::default_places_for_this_user();
    tofcomp::settings::DaemonConfig cfg =
        config_file.empty() ? tofcomp::settings::embedded_default_config()
                            : tofcomp::settings::load_daemon_config(config_file, places);
    tofcomp::settings::apply_command_line_overrides(overrides, cfg);
    // A user's own runtime folder may sit under /tmp: it is used only if it is theirs alone.
    const std::filesystem::path own_folder = places.socket.parent_path();
    const bool in_own_folder =
        !places.system && cfg.outputs.socket.path.parent_path() == own_folder;
    if (check_only) {
      std::printf("%s: %s\n", cfg.source.c_str(), check_configuration(cfg).c_str());
      return 0;
    }
    service::configure_logging(cfg.log.target, cfg.log.level,
                               instance.empty() ? std::string(service::kDefaultLogIdentity)
                                                : tofcomp::ipc::instance_log_identity(instance));
    logging = true;
    spdlog::info("tofcompd {} starting with {}", tofcomp::io::kVersion, cfg.source);
    if (!places.system) {
      spdlog::info(
          "not run as root: the socket, ring and recordings default to uid {}'s own "
          "places (docs/deployment.md)",
          tofcomp::ipc::current_user_environment().uid);
    }
    if (in_own_folder) make_private_directory(own_folder);
    Daemon daemon(cfg, config_file, overrides);
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
