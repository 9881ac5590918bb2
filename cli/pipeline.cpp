#include "cli/pipeline.hpp"

#include <chrono>
#include <ctime>

#include "cli/basis_spec.hpp"
#include "cli/version.hpp"
#include "core/em_test.hpp"
#include "core/error.hpp"

namespace tofcomp::cli {
namespace {

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

}  // namespace

ThermalFit fit_thermal(const MeasuredData& train, const MeasuredData* held_out,
                       const ThermalFitSettings& settings) {
  ThermalFit fit;
  fit.algorithm1 = core::identify_from_datasheet(settings.datasheet);
  core::PemOptions options;
  options.free = settings.free;
  fit.pem = core::identify_by_prediction_error(case_log(train, settings.ambient_fallback_c),
                                               fit.algorithm1, options);
  if (held_out != nullptr && held_out->temperature_time_s.size() >= 2) {
    const core::CaseTemperatureLog log = case_log(*held_out, settings.ambient_fallback_c);
    fit.has_held_out = true;
    fit.held_out_time_s = log.times_s;
    fit.held_out_measured_c = log.case_c;
    fit.held_out_predicted_c = core::predict_case_temperature(log, fit.pem.parameters);
    fit.held_out_paper_fit_percent =
        core::paper_fit_percent(fit.held_out_predicted_c, fit.held_out_measured_c);
    fit.held_out_nrmse_fit_percent =
        core::nrmse_fit_percent(fit.held_out_predicted_c, fit.held_out_measured_c);
  }
  return fit;
}

Training train_calibration(const MeasuredData& data, const TrainSettings& settings,
                           const MeasuredData* held_out) {
  data.require_true_ranges();
  Training t;
  t.thermal = fit_thermal(data, held_out, settings.thermal);
  const core::ThermalParameters& thermal = t.thermal.pem.parameters;
  t.junction =
      junction_at_ranges(data, thermal, settings.noise, settings.thermal.ambient_fallback_c);

  const core::Basis basis = parse_basis(settings.basis, t.junction.junction_c);
  const Eigen::MatrixXd h = basis.design_matrix(t.junction.junction_c);
  t.em = core::train_em(h, data.range_mm - data.true_range_mm, settings.em);

  io::Calibration& c = t.calibration;
  c.thermal = thermal;
  c.noise = settings.noise;
  c.ambient_c = settings.thermal.ambient_fallback_c;
  c.model.basis = basis;
  c.model.theta = t.em.theta;
  c.model.noise = t.em.mixture;
  c.provenance.data_set = data.source;
  c.provenance.created_utc = utc_now();
  c.provenance.software_version = std::string("tofcomp ") + kVersion;
  c.provenance.samples = static_cast<long>(data.range_mm.size());
  c.provenance.notes = "beam " + std::to_string(data.beam) + "; EM " +
                       std::to_string(t.em.iterations) + " iterations" +
                       (t.em.converged ? "" : " (iteration cap reached)");
  return t;
}

Compensation compensate(const MeasuredData& data, const io::Calibration& calibration) {
  Compensation out;
  out.junction =
      junction_at_ranges(data, calibration.thermal, calibration.noise, calibration.ambient_c);
  out.bias_mm = calibration.model.bias(out.junction.junction_c);
  if (calibration.extension) {
    const Eigen::VectorXd time_since_power_on_s = data.time_since_power_on();
    out.bias_mm += calibration.extension->covariate_bias(
        {data.range_time_s, out.junction.junction_c, time_since_power_on_s});
  }
  return out;
}

core::ExtendedMixture noise_of(const io::Calibration& calibration) {
  return calibration.extension ? calibration.extension->noise
                               : core::without_extensions(calibration.model.noise);
}

double held_out_log_likelihood(const MeasuredData& data, const io::Calibration& calibration,
                               const Compensation& compensation) {
  data.require_true_ranges();
  const core::ExtendedMixture noise = noise_of(calibration);
  core::ExtendedResponsibilities scratch;
  return core::extended_e_step(data.range_mm - data.true_range_mm - compensation.bias_mm,
                               noise.bin_of(compensation.junction.junction_c), noise, scratch);
}

core::Diagnosis diagnose(const MeasuredData& data, const io::Calibration& calibration) {
  constexpr double kRateHalfWindowS = 30.0;
  data.require_true_ranges();
  const Compensation compensation = compensate(data, calibration);
  core::DiagnosisInput input;
  input.time_s = data.range_time_s;
  input.junction_c = compensation.junction.junction_c;
  input.junction_rate_c_per_s =
      core::local_rate(data.range_time_s, compensation.junction.junction_c, kRateHalfWindowS);
  input.time_since_power_on_s = data.time_since_power_on();
  input.residual = data.range_mm - data.true_range_mm - compensation.bias_mm;
  return core::diagnose_residuals(input, noise_of(calibration).modes);
}

std::vector<WindowEvaluation> evaluate_windows(const MeasuredData& data,
                                               const io::Calibration& calibration,
                                               const Compensation& compensation,
                                               const std::vector<Eigen::Index>& windows,
                                               Eigen::Index stride,
                                               const std::function<void(double)>& progress) {
  bool has_truth = data.range_mm.size() > 0;
  for (const bool known : data.has_true_range) has_truth = has_truth && known;
  std::vector<WindowEvaluation> out;
  for (std::size_t w = 0; w < windows.size(); ++w) {
    if (progress) progress(static_cast<double>(w) / static_cast<double>(windows.size()));
    WindowEvaluation e;
    e.window = windows[w];
    e.estimates = calibration.extension
                      ? core::estimate_windows(
                            data.range_mm, compensation.bias_mm,
                            calibration.extension->noise.bin_of(compensation.junction.junction_c),
                            calibration.extension->noise, e.window, stride)
                      : core::estimate_windows(data.range_mm, compensation.bias_mm,
                                               calibration.model.noise, e.window, stride);
    e.has_truth = has_truth;
    if (has_truth) {
      const auto count = static_cast<Eigen::Index>(e.estimates.start.size());
      e.truth_mm.resize(count);
      for (Eigen::Index i = 0; i < count; ++i) {
        e.truth_mm[i] =
            data.true_range_mm.segment(e.estimates.start[static_cast<std::size_t>(i)], e.window)
                .mean();
      }
      e.em = core::error_moments(e.estimates.em_distance, e.truth_mm);
      e.raw = core::error_moments(e.estimates.raw_mean, e.truth_mm);
      e.bias_corrected = core::error_moments(e.estimates.bias_corrected_mean, e.truth_mm);
    }
    out.push_back(std::move(e));
  }
  if (progress) progress(1.0);
  return out;
}

}  // namespace tofcomp::cli
