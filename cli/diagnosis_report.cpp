#include "cli/diagnosis_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "cli/figure_data.hpp"
#include "cli/progress.hpp"
#include "cli/report_figure_data.hpp"
#include "cli/report_format.hpp"
#include "cli/report_renderer.hpp"
#include "cli/search_figure_data.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/version.hpp"

namespace tofcomp::cli {
namespace {

// Fewer held-out ranges than this make no window statistics worth a figure.
constexpr Eigen::Index kMinimumHeldOutRanges = 100;

// DIR and DIR/data, made if missing; throws naming DIR when that is impossible.
std::filesystem::path make_report_directory(const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code error;
  std::filesystem::create_directories(dir / "data", error);
  if (error || !std::filesystem::is_directory(dir / "data")) {
    throw core::Error("report directory " + directory + ": cannot create it" +
                      (error ? ": " + error.message() : std::string()));
  }
  return dir;
}

// The lengths of `wanted` that fit in `samples` ranges, sorted, each once.
std::vector<Eigen::Index> fitting_windows(std::vector<Eigen::Index> wanted, Eigen::Index samples) {
  std::erase_if(wanted, [&](Eigen::Index w) { return w < 1 || w > samples; });
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  return wanted;
}

}  // namespace

void check_report_possible(const std::string& directory) {
  make_report_directory(directory);
  find_report_renderer();
}

void write_diagnosis_report(const std::string& directory, const calibration::MeasuredData& measured,
                            const calibration::TrainSettings& settings,
                            const DiagnosisOutcome& diagnosis, const ReportSettings& report,
                            bool show_progress) {
  const std::filesystem::path dir = make_report_directory(directory);
  const ReportRenderer renderer = find_report_renderer();
  const std::filesystem::path data_dir = dir / "data";
  Progress progress("report", show_progress);

  // The diagnosis's held-out split (command_diagnose.cpp): train on the first half of the
  // power cycles, draw the figures of testing on the rest.
  const double split = calibration::split_time(measured, 0.5);
  const calibration::MeasuredData train = measured.slice(-1e300, split);
  const calibration::MeasuredData test = measured.slice(split, 1e300);
  test.require_true_ranges();
  if (test.range_mm.size() < kMinimumHeldOutRanges) {
    throw core::InvalidInput(
        fmt::format("{}: the held-out half (after t = {:.0f} s) has {} ranges; the report needs {}",
                    measured.source, split, test.range_mm.size(), kMinimumHeldOutRanges));
  }
  progress.update(0.02, "training on the first half");
  const calibration::Training t = calibration::train_calibration(train, settings, &test);
  const calibration::Compensation compensation = calibration::compensate(test, t.calibration);

  // Fig. 16-19: the three estimators of §8.4 on every window of each length.
  const Eigen::Index samples = test.range_mm.size();
  std::vector<Eigen::Index> report_windows = fitting_windows(report.windows, samples);
  if (report_windows.empty()) report_windows = {samples};
  std::vector<Eigen::Index> moment_windows = fitting_windows(report.moment_windows, samples);
  std::vector<Eigen::Index> all_windows = report_windows;
  all_windows.insert(all_windows.end(), moment_windows.begin(), moment_windows.end());
  all_windows = fitting_windows(all_windows, samples);
  const auto evaluations = calibration::evaluate_windows(
      test, t.calibration, compensation, all_windows, report.stride,
      [&](double f) { progress.update(0.1 + 0.3 * f, "window estimates"); });
  // Fig. 3, 4, 8, 11, 12, 13, 16, 17: the CSVs of `tofcomp evaluate --figures`.
  write_figure_data(data_dir.string(), test, t.calibration, compensation, evaluations, &t.thermal,
                    &t.em);
  write_error_moments(data_dir, evaluations);

  const TrainingResiduals residuals{t.junction.junction_c, train.range_mm - train.true_range_mm};
  const nlohmann::json glr = write_glr_data(
      data_dir, residuals, report.glr_orders, settings.em,
      [&](double f) { progress.update(0.4 + 0.45 * f, "Algorithm 2 over the candidate bases"); });
  const nlohmann::json trace = write_em_test_trace(
      data_dir, test, compensation, t.calibration.model.mixture, report.convergence_samples);
  progress.update(0.87, "timing EM testing");
  const nlohmann::json cost =
      write_em_test_cost(data_dir, residuals, test, compensation, report.cost_fourier_orders,
                         glr.at("fourier_f0_per_c").get<double>(), settings.em, report.cost_steps);

  const nlohmann::json diagnosis_samples =
      write_diagnosis_samples(data_dir, measured, diagnosis.trained, diagnosis.tests);
  progress.update(0.88, "the figures of the search's terms");
  const nlohmann::json search_terms =
      write_search_figure_data(data_dir, measured, diagnosis.search.calibration, diagnosis.search);

  const nlohmann::json context = {{"source", measured.source},
                                  {"beam", measured.beam},
                                  {"software_version", std::string("tofcomp ") + io::kVersion},
                                  {"split_time_s", split},
                                  {"training_samples", train.range_mm.size()},
                                  {"test_samples", samples},
                                  {"windows", report_windows},
                                  {"moment_windows", moment_windows},
                                  {"stride", report.stride},
                                  {"thermal_fit", to_json(t.thermal)},
                                  {"calibration", to_json(t.calibration)},
                                  {"diagnosis_calibration", to_json(diagnosis.trained)},
                                  {"search_calibration", to_json(diagnosis.search.calibration)},
                                  {"search_terms", search_terms},
                                  {"em_training_iterations", t.em.iterations},
                                  {"glr", glr},
                                  {"em_test_trace", trace},
                                  {"em_test_cost", cost},
                                  {"diagnosis_samples", diagnosis_samples}};
  io::write_file_atomically(data_dir / "context.json", context.dump(2) + "\n");
  io::write_file_atomically(data_dir / "diagnosis.json", diagnosis.json.dump(2) + "\n");

  progress.update(0.9, "drawing the figures");
  renderer.render(dir, show_progress);
  progress.done((dir / "index.html").string());
}

}  // namespace tofcomp::cli
