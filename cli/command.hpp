// The subcommands of `tofcomp`: each file cli/command_*.cpp registers one on the CLI11 app and
// runs it. Options common to every subcommand live in CommonOptions.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

namespace tofcomp::cli {

struct CommonOptions {
  bool json = false;   // print the result as one JSON document on stdout
  bool quiet = false;  // no progress on stderr
};

// What a subcommand returns to main: its result for --json, and the text for humans.
struct CommandResult {
  nlohmann::json json;
  std::string text;
  bool streamed = false;  // printed as it went (query subscribe): main prints nothing more
  int exit_status = 0;    // printed in full, yet some of the work failed (calibrate-dir): 1
};

using CommandRunner = std::function<CommandResult()>;

// Each register_* adds its subcommand to app and returns how to run it once parsed.
void register_simulate(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_thermal_fit(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_train(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_select(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_test(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_evaluate(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_diagnose(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_calibrate_dir(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_emulate(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_scan(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_query(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_replay(CLI::App& app, const CommonOptions& common, CommandRunner& run);
void register_shm_dump(CLI::App& app, const CommonOptions& common, CommandRunner& run);

}  // namespace tofcomp::cli
