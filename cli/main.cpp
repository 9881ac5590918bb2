// tofcomp: the command line over measured data — simulate, thermal-fit, train, select, test,
// evaluate, diagnose, calibrate-dir — and the LMS 200 link: an emulated device (emulate), a host
// (scan). Results go to stdout (text, or JSON with --json); progress and errors to stderr. Exit
// status: 0 success, 1 the work failed (the message says why; calibrate-dir: some recording
// failed, its row says why), 2 bad command line.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "cli/command.hpp"
#include "cli/unknown_argument_hint.hpp"
#include "core/error.hpp"
#include "io/help_format.hpp"
#include "io/version.hpp"

int main(int argc, char** argv) {
  using namespace tofcomp::cli;
  CLI::App app{
      "tofcomp: temperature and mode-hopping compensation for time-of-flight LiDARs "
      "(Alhashimi et al., Sensors 2015)"};
  tofcomp::io::use_gnu_help(app);
  app.set_version_flag("--version", std::string("tofcomp ") + tofcomp::io::kVersion);
  app.require_subcommand(1);
  app.fallthrough();  // --json and --quiet also after the subcommand
  CommonOptions common;
  app.add_flag("--json", common.json, "Print the result as JSON on stdout");
  app.add_flag("-q,--quiet", common.quiet, "Do not show progress on stderr");

  CommandRunner run;
  register_simulate(app, common, run);
  register_thermal_fit(app, common, run);
  register_train(app, common, run);
  register_select(app, common, run);
  register_test(app, common, run);
  register_evaluate(app, common, run);
  register_diagnose(app, common, run);
  register_calibrate_dir(app, common, run);
  register_emulate(app, common, run);
  register_scan(app, common, run);
  register_shm_dump(app, common, run);
  register_replay(app, common, run);
  register_query(app, common, run);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // A typo gets the suggestion alone: CLI11's own message for it ("A subcommand is required",
    // "The following arguments were not expected: 3 --bem") would come first and mislead.
    const std::string hint = unknown_argument_hint(app);
    if (!hint.empty()) {
      std::fputs(hint.c_str(), stderr);
      std::fputs("Run with --help for more information.\n", stderr);
      return 2;
    }
    return app.exit(e) == 0 ? 0 : 2;
  }

  const std::string name = app.get_subcommands().front()->get_name();
  try {
    const CommandResult result = run();
    if (result.streamed) {
      // already on stdout
    } else if (common.json) {
      std::cout << result.json.dump(2) << "\n";
    } else {
      std::cout << result.text;
    }
    return result.exit_status;
  } catch (const tofcomp::core::Error& e) {
    std::fprintf(stderr, "tofcomp %s: error: %s\n", name.c_str(), e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tofcomp %s: internal error: %s\n", name.c_str(), e.what());
  }
  return 1;
}
