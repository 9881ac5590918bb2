// Options that several subcommands share, registered in one place so that they mean one thing.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "calibration/model_search.hpp"
#include "calibration/training.hpp"

namespace tofcomp::cli {

// The most threads or jobs a command takes at once (--threads, --jobs).
inline constexpr int kMaxParallelism = 256;
// --threads or --jobs (`names`, CLI11's "-j,--jobs"): how many of `what` run at once, 0 (the
// default) one per core; the help says the results do not depend on it.
CLI::Option* add_parallelism_option(CLI::App& cmd, const std::string& names, int& count,
                                    const std::string& what);

// --figures DIR of evaluate and test (cli/figure_drawing.hpp): the paper's figures as PNG in
// DIR/figures/, their data as CSV in DIR/data/.
CLI::Option* add_figures_option(CLI::App& cmd, std::string& directory);

// --basis and --modes: chosen from the data.
inline constexpr const char* kAutoChoice = "auto";

struct DataOptions {
  std::string file;
  int beam = 0;
  const CLI::Option* beam_option = nullptr;
  // The beam when --beam was given.
  std::optional<int> given_beam() const;
  // Reads the beam; prints the reader's warnings on stderr.
  calibration::MeasuredData load() const;
};
std::shared_ptr<DataOptions> add_data_options(CLI::App& cmd);

struct ThermalOptions {
  std::string datasheet;  // empty: the bundled LMS 200 datasheet
  std::string free = "r2,c1,c2";
  const CLI::Option* free_option = nullptr;  // given: the paper's prediction-error method
  double prior_factor = 2.0;                 // one σ of the datasheet prior, as a factor
  double ambient_c = 22.0;
  std::vector<double> kalman_noise_levels;  // q_case, q_junction, r; empty: from the case log
  calibration::ThermalFitSettings settings() const;
  // The levels given with --kalman-noise; absent: training chooses them from the case log.
  std::optional<core::ThermalNoise> kalman_noise() const;
};
std::shared_ptr<ThermalOptions> add_thermal_options(CLI::App& cmd);

struct TrainingOptions {
  std::shared_ptr<ThermalOptions> thermal;
  std::string basis = kAutoChoice;  // chosen from the data (core/structure_search.hpp)
  std::string modes = kAutoChoice;
  bool paper_m_step = false;
  bool paper_init = false;
  int max_iterations = 1000;
  // ranges: the junction's P·R1 and R1·C1 completed from the ranges where they reject the
  // case-log fit's (calibration/junction_dynamics.hpp); case-log: the thermal fit's alone.
  std::string junction = "ranges";
  calibration::TrainSettings settings() const;
};
std::shared_ptr<TrainingOptions> add_training_options(CLI::App& cmd);

// The model search's options (calibration/model_search.hpp), as diagnose and calibrate-dir take
// them.
struct SearchOptions {
  std::string windows = "200,400,800";
  long stride = 10;
  double alpha = 0.05;
  int max_steps = 3;
  // threads: the fits run at once (0: one per core).
  calibration::ModelSearchOptions options(int threads) const;
};
std::shared_ptr<SearchOptions> add_search_options(CLI::App& cmd);

// "200,400,800" → window lengths. Throws core::InvalidInput naming the item at fault.
std::vector<Eigen::Index> parse_windows(const std::string& list);
// --windows=N,N,...: the list checked while the command line is read (a bad one is a usage
// error, status 2, before any work); `what` says what the lengths are for.
CLI::Option* add_windows_option(CLI::App& cmd, std::string& windows, const std::string& what);

}  // namespace tofcomp::cli
