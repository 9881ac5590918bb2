#include "cli/shared_options.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "calibration/measured_data_reader.hpp"
#include "cli/number_checks.hpp"
#include "core/error.hpp"
#include "io/bundled_datasheet.hpp"
#include "io/datasheet_file.hpp"

namespace tofcomp::cli {

CLI::Option* add_parallelism_option(CLI::App& cmd, const std::string& names, int& count,
                                    const std::string& what) {
  return cmd
      .add_option(names, count,
                  what +
                      " at once (0, the default: one per core; the results do not depend on "
                      "it)")
      ->check(between(0, kMaxParallelism));
}

CLI::Option* add_figures_option(CLI::App& cmd, std::string& directory) {
  return cmd
      .add_option("--figures", directory,
                  "Draw the paper's figures into DIR/figures/ (PNG; needs "
                  "python3-matplotlib), their data as CSV into DIR/data/")
      ->type_name("DIR");
}

namespace {

constexpr const char* kJunctionFromRanges = "ranges";
constexpr const char* kJunctionFromCaseLog = "case-log";
constexpr int kMaxModes = 10;

}  // namespace

calibration::MeasuredData DataOptions::load() const {
  std::vector<std::string> warnings;
  calibration::MeasuredData data = calibration::read_measured_data(file, beam, warnings);
  for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return data;
}

std::shared_ptr<DataOptions> add_data_options(CLI::App& cmd) {
  auto o = std::make_shared<DataOptions>();
  cmd.add_option("data", o->file, "Measured data (interchange CSV)")
      ->required()
      ->check(CLI::ExistingFile);
  o->beam_option =
      cmd.add_option("--beam", o->beam, "Beam index to analyse")->capture_default_str();
  return o;
}

std::optional<int> DataOptions::given_beam() const {
  if (beam_option != nullptr && beam_option->count() > 0) return beam;
  return std::nullopt;
}

calibration::ThermalFitSettings ThermalOptions::settings() const {
  calibration::ThermalFitSettings s;
  s.datasheet = io::datasheet_or_bundled(datasheet);
  s.ambient_fallback_c = ambient_c;
  s.method = free_option != nullptr && free_option->count() > 0
                 ? calibration::ThermalFitMethod::PredictionError
                 : calibration::ThermalFitMethod::DatasheetPrior;
  s.prior.prior_log_std = std::log(prior_factor);
  s.free = core::ThermalParameterMask{false, false, false, false, false};
  std::istringstream in(free);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name == "r1") {
      s.free.r1 = true;
    } else if (name == "r2") {
      s.free.r2 = true;
    } else if (name == "c1") {
      s.free.c1 = true;
    } else if (name == "c2") {
      s.free.c2 = true;
    } else if (name == "p") {
      s.free.power = true;
    } else {
      throw core::InvalidInput("--free: '" + name + "' is not one of r1, r2, c1, c2, p");
    }
  }
  return s;
}

std::optional<core::ThermalNoise> ThermalOptions::kalman_noise() const {
  if (kalman_noise_levels.empty()) return std::nullopt;
  core::ThermalNoise n;
  n.case_process_psd_k2_per_s = kalman_noise_levels[0];
  n.junction_process_psd_k2_per_s = kalman_noise_levels[1];
  n.measurement_variance_k2 = kalman_noise_levels[2];
  n.validate();
  return n;
}

std::shared_ptr<ThermalOptions> add_thermal_options(CLI::App& cmd) {
  auto o = std::make_shared<ThermalOptions>();
  cmd.add_option("--datasheet", o->datasheet,
                 "Algorithm 1 inputs (YAML): the start of the thermal fit and its prior; "
                 "default: the LMS 200's, config/lms200-datasheet.yaml as built into tofcomp")
      ->check(CLI::ExistingFile);
  cmd.add_option("--prior-factor", o->prior_factor,
                 "The datasheet prior's spread: each thermal parameter within this factor of "
                 "Algorithm 1's value at one standard deviation")
      ->capture_default_str()
      ->check(between(1.0001, 1e6));
  o->free_option =
      cmd.add_option("--free", o->free,
                     "Fit only these thermal parameters, of r1,r2,c1,c2,p, by the paper's "
                     "prediction-error method (the others fixed at Algorithm 1's values; it "
                     "refuses a log that does not determine them). Without it every parameter is "
                     "fitted with the datasheet as a prior")
          ->capture_default_str()
          ->type_name("PARAMETERS");
  cmd.add_option("--ambient", o->ambient_c, "Ambient °C when the data carry no ambient_c")
      ->capture_default_str();
  cmd.add_option("--kalman-noise", o->kalman_noise_levels,
                 "Junction-temperature filter noise (§3.3): case and junction process noise "
                 "(K²/s) and sensor variance (K²), e.g. 1e-6,1e-4,3.3e-4; default: chosen "
                 "from the case log by the innovations' likelihood")
      ->expected(3)
      ->delimiter(',');
  return o;
}

calibration::TrainSettings TrainingOptions::settings() const {
  calibration::TrainSettings s;
  s.thermal = thermal->settings();
  s.kalman_noise = thermal->kalman_noise();
  if (basis != kAutoChoice) s.basis = basis;
  if (modes != kAutoChoice) {
    std::size_t used = 0;
    int m = 0;
    try {
      m = std::stoi(modes, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != modes.size() || m < 1 || m > kMaxModes) {
      throw core::InvalidInput("--modes: '" + modes + "' is neither auto nor a mode count 1.." +
                               std::to_string(kMaxModes));
    }
    s.modes = m;
  }
  s.junction_source = junction == kJunctionFromRanges
                          ? calibration::JunctionSource::RangesWhereTheyReject
                          : calibration::JunctionSource::CaseLog;
  s.em.max_iterations = max_iterations;
  s.em.m_step = paper_m_step ? core::MStep::PaperAsPrinted : core::MStep::Exact;
  s.em.initialization =
      paper_init ? core::EmInitialization::Paper : core::EmInitialization::Quantiles;
  // Eq. 20 is defined for two modes: with --paper-init the paper's M, unless given.
  if (paper_init && !s.modes) s.modes = 2;
  return s;
}

std::shared_ptr<TrainingOptions> add_training_options(CLI::App& cmd) {
  auto o = std::make_shared<TrainingOptions>();
  o->thermal = add_thermal_options(cmd);
  cmd.add_option("--basis", o->basis,
                 "H(.): polynomial:N[:legendre|raw], fourier:N:F0, joined by +; auto: the family "
                 "and order that predict held-out ranges best (§7)")
      ->capture_default_str()
      ->type_name("BASIS");
  cmd.add_option("--modes", o->modes,
                 "Lasing modes M (1-" + std::to_string(kMaxModes) +
                     "); auto: the number that predicts held-out ranges best")
      ->capture_default_str()
      ->type_name("M");
  cmd.add_flag("--paper-m-step", o->paper_m_step, "Use Eq. 19 as printed (docs/em-m-step.md)");
  cmd.add_flag("--paper-init", o->paper_init,
               "Start from Eq. 20 (two modes only: --modes defaults to 2 with it)");
  cmd.add_option("--max-iterations", o->max_iterations, "EM iteration cap")
      ->capture_default_str()
      ->check(at_least(1));
  cmd.add_option("--junction", o->junction,
                 "The junction's rise P·R1 and time constant R1·C1, which a case log barely "
                 "shows: ranges (from the ranges' likelihood under the datasheet's prior, where "
                 "it rejects the thermal fit's) or case-log (the thermal fit's alone)")
      ->capture_default_str()
      ->check(CLI::IsMember({kJunctionFromRanges, kJunctionFromCaseLog}))
      ->type_name("FROM");
  return o;
}

calibration::ModelSearchOptions SearchOptions::options(int threads) const {
  calibration::ModelSearchOptions o;
  o.windows = parse_windows(windows);
  o.stride = stride;
  o.alpha = alpha;
  o.max_steps = max_steps;
  o.threads = threads;
  return o;
}

std::shared_ptr<SearchOptions> add_search_options(CLI::App& cmd) {
  auto o = std::make_shared<SearchOptions>();
  add_windows_option(cmd, o->windows, "Window lengths of the held-out d hat comparison");
  cmd.add_option("--stride", o->stride, "Ranges between held-out windows")
      ->capture_default_str()
      ->check(at_least(1));
  cmd.add_option("--alpha", o->alpha,
                 "Family-wise false-alarm level: data with nothing missing keep a term with at "
                 "most this probability")
      ->capture_default_str()
      ->check(between(1e-9, 0.5));
  cmd.add_option("--max-steps", o->max_steps,
                 "Steps of the forward selection at most (each adds the term it names when it "
                 "passes)")
      ->capture_default_str()
      ->check(between(1, 10));
  return o;
}

CLI::Option* add_windows_option(CLI::App& cmd, std::string& windows, const std::string& what) {
  return cmd.add_option("--windows", windows, what + ", comma separated")
      ->capture_default_str()
      ->check(parsed_by([](const std::string& text) { parse_windows(text); },
                        "--windows: ", "N,N,..."));
}

std::vector<Eigen::Index> parse_windows(const std::string& list) {
  std::vector<Eigen::Index> out;
  std::istringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      std::size_t used = 0;
      const long value = std::stol(item, &used);
      if (used != item.size() || value < 1) throw std::invalid_argument(item);
      out.push_back(value);
    } catch (const std::exception&) {
      throw core::InvalidInput("--windows: '" + item + "' is not a window length >= 1");
    }
  }
  if (out.empty()) throw core::InvalidInput("--windows: no window length given");
  return out;
}

}  // namespace tofcomp::cli
