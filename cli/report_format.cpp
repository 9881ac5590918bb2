#include "cli/report_format.hpp"

#include <fmt/format.h>

#include "cli/mixture_format.hpp"
#include "cli/structure_format.hpp"

namespace tofcomp::cli {

nlohmann::json to_json(const core::ErrorMoments& m) {
  return {{"count", m.count},
          {"mean_error_mm", m.mean_error},
          {"error_variance_mm2", m.error_variance},
          {"mean_absolute_error_mm", m.mean_absolute_error},
          {"absolute_error_variance_mm2", m.absolute_error_variance},
          {"rmse_mm", m.rmse}};
}

namespace {

// A direction's components smaller than this are left out of its description.
constexpr double kDirectionComponentShown = 0.05;

nlohmann::json thermal_json(const core::ThermalParameters& p) {
  return {{"r1_k_per_w", p.r1_k_per_w},
          {"r2_k_per_w", p.r2_k_per_w},
          {"c1_j_per_k", p.c1_j_per_k},
          {"c2_j_per_k", p.c2_j_per_k},
          {"power_w", p.power_w}};
}

std::string thermal_line(const core::ThermalParameters& p) {
  return fmt::format("R1 {:.4g} K/W, R2 {:.4g} K/W, C1 {:.4g} J/K, C2 {:.4g} J/K, P {:.4g} W",
                     p.r1_k_per_w, p.r2_k_per_w, p.c1_j_per_k, p.c2_j_per_k, p.power_w);
}

// Per parameter: the estimate's relative standard deviation and whether the data or the datasheet
// set it; then the directions the data see less than the prior.
std::string map_fit_detail_text(const core::MapFitResult& m) {
  std::string out;
  const auto values = core::thermal_parameter_values(m.parameters);
  for (const core::ThermalParameter p : core::kThermalParameters) {
    const auto i = static_cast<std::size_t>(p);
    out += fmt::format(
        "    {:<2} {:10.4g} ± {:5.1f} %  (the log removed {:.0f} % of the datasheet's variance)\n",
        core::thermal_parameter_name(p), values[i], 100.0 * m.relative_std[i],
        100.0 * m.data_share[i]);
  }
  for (const core::PriorHeldDirection& d : m.prior_held_directions) {
    std::string direction;
    for (const core::ThermalParameter p : core::kThermalParameters) {
      const double c = d.log_direction[static_cast<std::size_t>(p)];
      if (std::abs(c) < kDirectionComponentShown) continue;
      direction += fmt::format("{}{:.2f} log {}",
                               direction.empty() ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + "),
                               std::abs(c), core::thermal_parameter_name(p));
    }
    out += fmt::format("    held by the datasheet along {} (data/prior information {:.2g})\n",
                       direction, d.data_over_prior);
  }
  out += fmt::format("    residuals: lag-1 correlation {:.3f}, {:.0f} independent readings\n",
                     m.residual_lag1_correlation, m.effective_samples);
  return out;
}

}  // namespace

nlohmann::json to_json(const calibration::ThermalFit& fit) {
  const core::ThermalFitResult& training = fit.training();
  nlohmann::json j = {{"algorithm1", thermal_json(fit.algorithm1)},
                      {"method", fit.map ? "datasheet_prior" : "prediction_error"},
                      {"identified", thermal_json(training.parameters)},
                      {"iterations", training.iterations},
                      {"converged", training.converged},
                      {"training_rms_residual_c", training.rms_residual_c},
                      {"training_paper_fit_percent", training.paper_fit_percent},
                      {"training_nrmse_fit_percent", training.nrmse_fit_percent}};
  if (fit.map) {
    const core::MapFitResult& m = *fit.map;
    nlohmann::json parameters = nlohmann::json::array();
    const auto values = core::thermal_parameter_values(m.parameters);
    const auto prior = core::thermal_parameter_values(m.prior);
    for (const core::ThermalParameter p : core::kThermalParameters) {
      const auto i = static_cast<std::size_t>(p);
      parameters.push_back({{"name", core::thermal_parameter_name(p)},
                            {"value", values[i]},
                            {"datasheet", prior[i]},
                            {"relative_std", m.relative_std[i]},
                            {"data_share", m.data_share[i]},
                            {"held_at_datasheet", m.held[i]}});
    }
    nlohmann::json directions = nlohmann::json::array();
    for (const core::PriorHeldDirection& d : m.prior_held_directions) {
      directions.push_back(
          {{"log_direction", d.log_direction}, {"data_over_prior", d.data_over_prior}});
    }
    j["parameters"] = parameters;
    j["prior_held_directions"] = directions;
    j["effective_samples"] = m.effective_samples;
    j["residual_lag1_correlation"] = m.residual_lag1_correlation;
  }
  if (fit.has_held_out) {
    j["held_out_paper_fit_percent"] = fit.held_out_paper_fit_percent;
    j["held_out_nrmse_fit_percent"] = fit.held_out_nrmse_fit_percent;
  }
  return j;
}

nlohmann::json to_json(const core::Calibration& c) {
  return {{"thermal", thermal_json(c.thermal)},
          {"basis", c.model.basis.describe()},
          {"theta_mm",
           std::vector<double>(c.model.theta.data(), c.model.theta.data() + c.model.theta.size())},
          {"modes", modes_json(c.model.mixture)},
          {"samples", c.provenance.samples},
          {"data_set", c.provenance.data_set}};
}

nlohmann::json training_json(const calibration::Training& t) {
  return {{"calibration", to_json(t.calibration)}, {"thermal_fit", to_json(t.thermal)},
          {"choices", choices_json(t)},           {"em_iterations", t.em.iterations},
          {"em_converged", t.em.converged},       {"log_likelihood", t.em.log_likelihood},
          {"final_fit_dropped_modes", t.final_fit_dropped_modes}};
}

nlohmann::json to_json(const std::vector<calibration::WindowEvaluation>& evaluations) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& e : evaluations) {
    nlohmann::json j = {{"window", e.window},
                        {"windows", e.estimates.start.size()},
                        {"windows_left_out", e.windows_left_out},
                        {"cramer_rao_mae_mm", e.cramer_rao_mae_mm}};
    if (e.has_truth && e.em.count == 0) {  // every window left out: no error to state
      j["em"] = to_json(e.em);
      j["em_inside_trained"] = to_json(e.em_inside_trained);
      j["em_beyond_trained"] = to_json(e.em_beyond_trained);
    } else if (e.has_truth) {
      j["em"] = to_json(e.em);
      j["raw_mean"] = to_json(e.raw);
      j["bias_corrected_mean"] = to_json(e.bias_corrected);
      j["mae_improvement"] = e.raw.mean_absolute_error / e.em.mean_absolute_error;
      j["mae_over_cramer_rao"] = e.em.mean_absolute_error / e.cramer_rao_mae_mm;
      j["em_inside_trained"] = to_json(e.em_inside_trained);
      j["em_beyond_trained"] = to_json(e.em_beyond_trained);
    } else {
      j["em_distance_mm"] =
          std::vector<double>(e.estimates.em_distance.data(),
                              e.estimates.em_distance.data() + e.estimates.em_distance.size());
    }
    out.push_back(j);
  }
  return out;
}

std::string thermal_fit_text(const calibration::ThermalFit& fit) {
  std::string out;
  out += "thermal model (§3)\n";
  out += "  Algorithm 1 (datasheet): " + thermal_line(fit.algorithm1) + "\n";
  if (fit.map) {
    out += "  fit, datasheet as prior: " + thermal_line(fit.identified()) + "\n";
    out += map_fit_detail_text(*fit.map);
  } else {
    out += "  prediction-error fit:    " + thermal_line(fit.identified()) + "\n";
  }
  out += fmt::format(
      "  training fit: RMS {:.4f} °C, Eq. 26 {:.5f} %, NRMSE fit {:.2f} % ({} "
      "iterations{})\n",
      fit.training().rms_residual_c, fit.training().paper_fit_percent,
      fit.training().nrmse_fit_percent, fit.training().iterations,
      fit.training().converged ? "" : ", not converged");
  if (fit.has_held_out) {
    out += fmt::format("  held-out fit: Eq. 26 {:.5f} % (paper: 92.79 %), NRMSE fit {:.2f} %\n",
                       fit.held_out_paper_fit_percent, fit.held_out_nrmse_fit_percent);
  }
  return out;
}

std::string calibration_text(const core::Calibration& c) {
  return "measurement model (Eq. 8): basis " + c.model.basis.describe() + "\n" +
         modes_text(c.model.mixture);
}

std::string window_table_text(const std::vector<calibration::WindowEvaluation>& evaluations) {
  std::string out =
      "mean of y - H theta - sum pi mu: the window mean less the temperature bias and the modes' "
      "common offset sum_i pi_i mu_i (centred, so that it estimates d)\n";
  out += fmt::format("{:>7} {:>8}  {:<30} {:>9} {:>9} {:>11} {:>9}\n", "window", "windows",
                     "estimator", "ME mm", "MAE mm", "var|e| mm2", "RMSE mm");
  for (const auto& e : evaluations) {
    if (!e.has_truth) {
      out += fmt::format("{:>7} {:>8}  (no true distance in the data: no errors)\n", e.window,
                         e.estimates.start.size());
      continue;
    }
    if (e.em.count == 0) {
      out += fmt::format("{:>7} {:>8}  (every window held a range that is not still: no errors)\n",
                         e.window, 0);
      continue;
    }
    const std::pair<const char*, const core::ErrorMoments*> rows[] = {
        {"raw mean (y bar)", &e.raw},
        {"mean of y - H theta - sum pi mu", &e.bias_corrected},
        {"EM d hat", &e.em}};
    for (const auto& [name, m] : rows) {
      out += fmt::format("{:>7} {:>8}  {:<30} {:>9.3f} {:>9.3f} {:>11.3f} {:>9.3f}\n", e.window,
                         e.estimates.start.size(), name, m->mean_error, m->mean_absolute_error,
                         m->absolute_error_variance, m->rmse);
    }
    out += fmt::format("{:>7} {:>8}  MAE raw / MAE EM = {:.2f}\n", e.window, "",
                       e.raw.mean_absolute_error / e.em.mean_absolute_error);
    out +=
        fmt::format("{:>7} {:>8}  Cramér–Rao bound {:.3f} mm: MAE EM / bound = {:.2f}\n", e.window,
                    "", e.cramer_rao_mae_mm, e.em.mean_absolute_error / e.cramer_rao_mae_mm);
    const std::pair<const char*, const core::ErrorMoments*> apart[] = {
        {"inside the trained junction range", &e.em_inside_trained},
        {"beyond it (bias extrapolated)", &e.em_beyond_trained}};
    for (const auto& [where, m] : apart) {
      if (m->count == 0) continue;
      out += fmt::format("{:>7} {:>8}  EM d hat {}: MAE {:.3f} mm = {:.2f} × bound\n", e.window,
                         m->count, where, m->mean_absolute_error,
                         m->mean_absolute_error / e.cramer_rao_mae_mm);
    }
  }
  return out;
}

}  // namespace tofcomp::cli
