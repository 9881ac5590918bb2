#include "cli/report_figure_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "core/basis.hpp"
#include "core/em_test.hpp"
#include "core/error.hpp"
#include "core/model_extension.hpp"
#include "core/model_selection.hpp"
#include "io/atomic_file.hpp"

namespace tofcomp::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A message fit for one CSV cell.
std::string csv_cell(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

struct Candidate {
  std::string family;
  int order;
  core::Basis basis;
};

std::vector<Candidate> glr_candidates(const Eigen::VectorXd& junction_c, GlrOrders orders,
                                      double f0_per_c) {
  std::vector<Candidate> out;
  for (int n = 1; n <= orders.polynomial; ++n) {
    out.push_back({"polynomial", n, core::Basis::polynomial(n, junction_c)});
  }
  for (int n = 1; n <= orders.fourier; ++n) {
    out.push_back({"fourier", n, core::Basis::fourier(n, f0_per_c)});
  }
  return out;
}

}  // namespace

nlohmann::json write_glr_data(const std::filesystem::path& directory,
                              const TrainingResiduals& training, GlrOrders orders,
                              const core::EmTrainOptions& em,
                              const std::function<void(double)>& progress) {
  const Clock::time_point start = Clock::now();
  const double span_c =
      std::max(training.junction_c.maxCoeff() - training.junction_c.minCoeff(), 1e-3);
  const double f0_per_c = 1.0 / (2.0 * span_c);
  const std::vector<Candidate> candidates = glr_candidates(training.junction_c, orders, f0_per_c);
  core::SelectionOptions options;
  options.em = em;
  options.em.record_trace = false;

  std::string csv =
      "family,order,columns,ok,glr,bic,held_out_log_likelihood_per_sample,converged,error\n";
  double null_log_likelihood = 0.0;
  // One candidate at a time, for progress; each GLR is against the same null (Eq. 28).
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    progress(static_cast<double>(i) / static_cast<double>(candidates.size()));
    const Candidate& c = candidates[i];
    const core::SelectionResult r =
        core::select_model({c.basis}, training.junction_c, training.y_minus_d, options);
    null_log_likelihood = r.null_log_likelihood;
    const core::CandidateScore& s = r.scores.front();
    csv +=
        s.ok ? fmt::format("{},{},{},1,{},{},{},{},\n", c.family, c.order, s.columns, s.glr, s.bic,
                           s.held_out_log_likelihood, s.converged ? 1 : 0)
             : fmt::format("{},{},{},0,,,,,{}\n", c.family, c.order, s.columns, csv_cell(s.error));
  }
  progress(1.0);
  io::write_file_atomically(directory / "glr.csv", csv);
  return {{"max_polynomial_order", orders.polynomial},
          {"max_fourier_order", orders.fourier},
          {"fourier_f0_per_c", f0_per_c},
          {"training_samples", training.y_minus_d.size()},
          {"null_log_likelihood", null_log_likelihood},
          {"seconds", seconds_since(start)}};
}

nlohmann::json write_em_test_trace(const std::filesystem::path& directory,
                                   const calibration::MeasuredData& test,
                                   const calibration::Compensation& compensation,
                                   const core::MixtureParameters& mixture, Eigen::Index samples) {
  const Eigen::Index k = std::min(samples, test.range_mm.size());
  const Eigen::VectorXd y = test.range_mm.head(k);
  core::EmTestOptions options;
  options.record_trace = true;
  const double start = y.mean();  // §6: the paper's initial d̂ = 1ᵀy / K
  const core::EmTestResult fit =
      core::test_em(y, compensation.bias_mm.head(k), mixture, options, start);
  const double truth = test.true_range_mm.head(k).mean();
  std::string csv = "iteration,distance_mm,true_range_mm\n";
  csv += fmt::format("0,{},{}\n", start, truth);
  for (std::size_t i = 0; i < fit.distance_trace.size(); ++i) {
    csv += fmt::format("{},{},{}\n", i + 1, fit.distance_trace[i], truth);
  }
  io::write_file_atomically(directory / "em_test_trace.csv", csv);
  return {{"samples", k}, {"iterations", fit.iterations}, {"converged", fit.converged}};
}

nlohmann::json write_em_test_cost(const std::filesystem::path& directory,
                                  const TrainingResiduals& training,
                                  const calibration::MeasuredData& test,
                                  const calibration::Compensation& compensation,
                                  const std::vector<int>& fourier_orders, double f0_per_c,
                                  const core::EmTrainOptions& em, int steps) {
  constexpr int kPoints = 10;
  constexpr int kRepetitions = 5;
  const Eigen::Index total = test.range_mm.size();
  core::EmTestOptions options;
  options.max_iterations = steps;
  options.distance_tolerance = 1e-300;  // in effect: exactly `steps` iterations

  std::string csv = "basis,fourier_order,columns,samples,seconds,iterations\n";
  nlohmann::json bases = nlohmann::json::array();
  nlohmann::json left_out = nlohmann::json::array();
  core::EmTrainOptions train_options = em;
  train_options.record_trace = false;
  for (const int order : fourier_orders) {
    const core::Basis basis = core::Basis::fourier(order, f0_per_c);
    core::EmTrainResult model;
    try {
      model = core::train_em(basis.design_matrix(training.junction_c), training.y_minus_d,
                             train_options);
    } catch (const core::Error& e) {
      // Too many columns for the temperatures these data span (end of §5): no model to time.
      left_out.push_back({{"basis", basis.describe()}, {"error", e.what()}});
      continue;
    }
    bases.push_back(basis.describe());
    for (int p = 1; p <= kPoints; ++p) {
      const Eigen::Index k = std::max<Eigen::Index>(1, total * p / kPoints);
      double best = 1e300;
      int iterations = 0;
      for (int r = 0; r < kRepetitions; ++r) {
        const Clock::time_point start = Clock::now();
        const Eigen::VectorXd bias =
            basis.design_matrix(compensation.junction.junction_c.head(k)) * model.theta;
        const core::EmTestResult fit =
            core::test_em(test.range_mm.head(k), bias, model.mixture, options);
        best = std::min(best, seconds_since(start));
        iterations = fit.iterations;
      }
      csv += fmt::format("{},{},{},{},{},{}\n", csv_cell(basis.describe()), order, basis.columns(),
                         k, best, iterations);
    }
  }
  io::write_file_atomically(directory / "em_test_cost.csv", csv);
  return {
      {"bases", bases}, {"left_out", left_out}, {"steps", steps}, {"repetitions", kRepetitions}};
}

void write_error_moments(const std::filesystem::path& directory,
                         const std::vector<calibration::WindowEvaluation>& evaluations) {
  std::string csv =
      "window,estimator,count,mean_error_mm,error_variance_mm2,mean_absolute_error_mm,"
      "absolute_error_variance_mm2,rmse_mm,cramer_rao_mae_mm\n";
  for (const calibration::WindowEvaluation& e : evaluations) {
    if (!e.has_truth) continue;
    const std::pair<const char*, const core::ErrorMoments*> rows[] = {
        {"raw_mean", &e.raw}, {"bias_corrected_mean", &e.bias_corrected}, {"em_distance", &e.em}};
    for (const auto& [name, m] : rows) {
      csv += fmt::format("{},{},{},{},{},{},{},{},{}\n", e.window, name, m->count, m->mean_error,
                         m->error_variance, m->mean_absolute_error, m->absolute_error_variance,
                         m->rmse, e.cramer_rao_mae_mm);
    }
  }
  io::write_file_atomically(directory / "moments.csv", csv);
}

nlohmann::json write_diagnosis_samples(const std::filesystem::path& directory,
                                       const calibration::MeasuredData& measured,
                                       const core::Calibration& trained,
                                       const core::Diagnosis& diagnosis) {
  const calibration::Compensation compensation = calibration::compensate(measured, trained);
  const Eigen::VectorXd time_since_power_on_s = measured.time_since_power_on();
  const Eigen::VectorXd heating_rate_c_per_min =
      60.0 * core::local_rate(measured.range_time_s, compensation.junction.junction_c,
                              core::kHeatingRateHalfWindowS);
  const Eigen::Index n = measured.range_mm.size();
  if (diagnosis.mode.size() != n || diagnosis.compensated.size() != n) {
    throw core::InvalidInput(
        fmt::format("the diagnosis has {} ranges, the data {}", diagnosis.mode.size(), n));
  }
  std::string csv =
      "time_s,time_since_power_on_s,range_mm,true_range_mm,junction_c,bias_mm,residual_mm,mode,"
      "e_mm,heating_rate_c_per_min\n";
  for (Eigen::Index k = 0; k < n; ++k) {
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", measured.range_time_s[k],
                       time_since_power_on_s[k], measured.range_mm[k], measured.true_range_mm[k],
                       compensation.junction.junction_c[k], compensation.bias_mm[k],
                       measured.range_mm[k] - measured.true_range_mm[k] - compensation.bias_mm[k],
                       diagnosis.mode[k], diagnosis.compensated[k], heating_rate_c_per_min[k]);
  }
  io::write_file_atomically(directory / "diagnosis_samples.csv", csv);
  return {{"heating_rate_half_window_s", core::kHeatingRateHalfWindowS}};
}

}  // namespace tofcomp::cli
