#include "cli/figure_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "core/em_test.hpp"
#include "io/atomic_file.hpp"

namespace tofcomp::cli {
namespace {

std::string samples_csv(const calibration::MeasuredData& test, const core::Calibration& calibration,
                        const calibration::Compensation& compensation) {
  const int modes = calibration.model.mixture.modes();
  // Mode posteriors at the EM estimate of the whole test record (Eq. 22).
  const core::EmTestResult fit =
      core::test_em(test.range_mm, compensation.bias_mm, calibration.model.mixture);
  const bool has_truth = std::all_of(test.has_true_range.begin(), test.has_true_range.end(),
                                     [](bool known) { return known; });
  const Eigen::VectorXd time_since_power_on_s = test.time_since_power_on();
  std::string out = "time_s,time_since_power_on_s,range_mm,junction_c,bias_mm";
  for (int i = 0; i < modes; ++i) out += fmt::format(",posterior_mode{}", i + 1);
  out += ",most_probable_mode";
  out += has_truth ? ",compensated_mm,true_range_mm\n" : ",compensated_mm\n";
  for (Eigen::Index k = 0; k < test.range_mm.size(); ++k) {
    Eigen::Index best = 0;
    fit.responsibilities.row(k).maxCoeff(&best);
    out +=
        fmt::format("{},{},{},{},{}", test.range_time_s[k], time_since_power_on_s[k],
                    test.range_mm[k], compensation.junction.junction_c[k], compensation.bias_mm[k]);
    for (int i = 0; i < modes; ++i) out += fmt::format(",{}", fit.responsibilities(k, i));
    out += fmt::format(",{}", best);
    out += fmt::format(
        ",{}", test.range_mm[k] - compensation.bias_mm[k] - calibration.model.mixture.mean[best]);
    out += has_truth ? fmt::format(",{}\n", test.true_range_mm[k]) : "\n";
  }
  return out;
}

std::string windows_csv(const calibration::WindowEvaluation& e) {
  std::string out = "start,em_distance_mm,em_distance_std_mm,raw_mean_mm,bias_corrected_mean_mm";
  out += e.has_truth ? ",true_range_mm\n" : "\n";
  for (std::size_t i = 0; i < e.estimates.start.size(); ++i) {
    const auto w = static_cast<Eigen::Index>(i);
    out += fmt::format("{},{},{},{},{}", e.estimates.start[i], e.estimates.em_distance[w],
                       e.estimates.em_distance_std[w], e.estimates.raw_mean[w],
                       e.estimates.bias_corrected_mean[w]);
    out += e.has_truth ? fmt::format(",{}\n", e.truth_mm[w]) : "\n";
  }
  return out;
}

std::string thermal_csv(const calibration::ThermalFit& fit) {
  std::string out = "time_s,measured_case_c,predicted_case_c\n";
  for (Eigen::Index k = 0; k < fit.held_out_time_s.size(); ++k) {
    out += fmt::format("{},{},{}\n", fit.held_out_time_s[k], fit.held_out_measured_c[k],
                       fit.held_out_predicted_c[k]);
  }
  return out;
}

std::string convergence_csv(const core::EmTrainResult& em) {
  const int modes = em.mixture.modes();
  std::string out = "iteration";
  for (int i = 1; i <= modes; ++i) out += fmt::format(",mean{0}_mm,variance{0}_mm2,weight{0}", i);
  out += ",log_likelihood\n";
  for (std::size_t it = 0; it < em.trace.size(); ++it) {
    out += fmt::format("{}", it);
    for (int i = 0; i < modes; ++i) {
      out += fmt::format(",{},{},{}", em.trace[it].mean[i], em.trace[it].variance[i],
                         em.trace[it].weight[i]);
    }
    out += fmt::format(",{}\n", em.trace[it].log_likelihood);
  }
  return out;
}

}  // namespace

void write_figure_data(const std::string& directory, const calibration::MeasuredData& test,
                       const core::Calibration& calibration,
                       const calibration::Compensation& compensation,
                       const std::vector<calibration::WindowEvaluation>& windows,
                       const calibration::ThermalFit* thermal,
                       const core::EmTrainResult* training) {
  std::filesystem::create_directories(directory);
  const std::filesystem::path dir(directory);
  io::write_file_atomically(dir / "samples.csv", samples_csv(test, calibration, compensation));
  for (const auto& e : windows) {
    io::write_file_atomically(dir / fmt::format("windows_{}.csv", e.window), windows_csv(e));
  }
  if (thermal != nullptr && thermal->has_held_out) {
    io::write_file_atomically(dir / "thermal_fit.csv", thermal_csv(*thermal));
  }
  if (training != nullptr) {
    io::write_file_atomically(dir / "em_convergence.csv", convergence_csv(*training));
  }
}

}  // namespace tofcomp::cli
