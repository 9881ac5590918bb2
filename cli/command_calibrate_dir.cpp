// tofcomp calibrate-dir DIR -o OUT [-j N]: fleet recalibration offline. Every recording of DIR
// (*.csv, the interchange CSV with a known distance) is trained as `tofcomp train` trains and
// diagnosed as `tofcomp diagnose` diagnoses, N recordings at once
// (calibration/recording_batch.hpp). For each recording R, OUT/R.yaml is the calibration to
// deploy (with the terms the search kept) and OUT/R.json everything of its training and search,
// or its error. A table of the results goes to stdout, progress to stderr; the exit status is 1
// when any recording could not be calibrated.
#include <fmt/format.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "calibration/parallel_for.hpp"
#include "calibration/recording_batch.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "cli/recording_batch_format.hpp"
#include "cli/shared_options.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::cli {
namespace {

struct BatchOptions {
  std::string directory;
  std::string output_directory;
  int beam = 0;
  int jobs = 0;
};

// JSON files are indented like --json output.
constexpr int kJsonIndent = 2;

void create_output_directory(const std::filesystem::path& directory) {
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec || !std::filesystem::is_directory(directory)) {
    throw core::InvalidInput(fmt::format("--output-dir {}: cannot create it{}", directory.string(),
                                         ec ? ": " + ec.message() : ""));
  }
}

}  // namespace

void register_calibrate_dir(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "calibrate-dir",
      "Calibrate and diagnose every recording (*.csv) of a directory, several at once: for "
      "each recording R, OUT/R.yaml (the calibration, with any term diagnose keeps) and "
      "OUT/R.json (its training and search, or its error); a table of the results");
  auto o = std::make_shared<BatchOptions>();
  cmd->add_option("directory", o->directory, "Directory of recordings (interchange CSV, *.csv)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output-dir", o->output_directory,
                  "Directory for the calibrations and the per-recording JSON (created if missing)")
      ->required()
      ->type_name("DIR");
  cmd->add_option("--beam", o->beam, "Beam index to analyse in every recording")
      ->capture_default_str();
  add_parallelism_option(*cmd, "-j,--jobs", o->jobs, "Recordings calibrated");
  auto training = add_training_options(*cmd);
  auto search = add_search_options(*cmd);
  cmd->callback([&common, &run, o, training, search] {
    run = [&common, o, training, search] {
      const std::vector<std::filesystem::path> recordings =
          calibration::recordings_in(o->directory);
      const std::filesystem::path out_dir(o->output_directory);
      create_output_directory(out_dir);
      calibration::BatchSettings settings;
      settings.training = training->settings();
      settings.search = search->options(0);
      settings.beam = o->beam;
      settings.jobs = o->jobs;

      const std::size_t total = recordings.size();
      const bool progress = !common.quiet;
      if (progress) {
        std::fprintf(stderr, "calibrate-dir: %zu recordings, %d at once\n", total,
                     std::min<int>(calibration::thread_count(o->jobs), static_cast<int>(total)));
      }
      std::vector<nlohmann::json> rows(total);
      std::size_t done = 0;
      calibration::calibrate_recordings(
          recordings, settings,
          [&](std::size_t i) {
            if (progress) {
              std::fprintf(stderr, "calibrate-dir: started %s\n",
                           recordings[i].filename().string().c_str());
            }
          },
          [&](std::size_t i, calibration::RecordingOutcome&& outcome) {
            const std::string stem = recordings[i].stem().string();
            const std::filesystem::path calibration_file = out_dir / (stem + ".yaml");
            for (const auto& w : outcome.warnings) {
              std::fprintf(stderr, "warning: %s: %s\n", recordings[i].string().c_str(), w.c_str());
            }
            try {
              if (outcome.calibrated()) {
                io::write_calibration_file(calibration_file.string(), outcome.calibration());
              }
            } catch (const core::Error& e) {
              outcome.error = fmt::format("writing {}: {}", calibration_file.string(), e.what());
              outcome.training.reset();
              outcome.search.reset();
            }
            nlohmann::json record =
                recording_json(outcome, settings.search, calibration_file.string());
            try {
              io::write_file_atomically(out_dir / (stem + ".json"),
                                        record.dump(kJsonIndent) + "\n");
            } catch (const core::Error& e) {
              record["status"] = "failed";
              record["error"] = fmt::format("writing {}.json: {}", stem, e.what());
              record["training"] = nullptr;
              record["search"] = nullptr;
            }
            rows[i] = recording_row(record);
            rows[i]["recording"] = recordings[i].filename().string();
            ++done;
            if (progress) {
              const std::string error = rows[i]["error"].get<std::string>();
              std::fprintf(stderr, "calibrate-dir: [%zu/%zu] %s: %s%s (%.1f s)\n", done, total,
                           recordings[i].filename().string().c_str(),
                           rows[i]["status"].get<std::string>().c_str(),
                           error.empty() ? "" : (": " + error).c_str(), outcome.seconds);
            }
          });

      const auto failed = static_cast<std::size_t>(
          std::count_if(rows.begin(), rows.end(),
                        [](const nlohmann::json& r) { return r["status"] == "failed"; }));
      CommandResult result;
      result.json = {{"directory", o->directory},
                     {"output_dir", o->output_directory},
                     {"recordings", rows},
                     {"calibrated", total - failed},
                     {"failed", failed}};
      result.text = batch_table_text(rows, settings.search.windows);
      result.exit_status = failed == 0 ? 0 : 1;
      return result;
    };
  });
}

}  // namespace tofcomp::cli
