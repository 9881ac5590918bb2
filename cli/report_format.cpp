#include "cli/report_format.hpp"

#include <fmt/format.h>

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

}  // namespace

nlohmann::json to_json(const calibration::ThermalFit& fit) {
  nlohmann::json j = {{"algorithm1", thermal_json(fit.algorithm1)},
                      {"identified", thermal_json(fit.pem.parameters)},
                      {"pem_iterations", fit.pem.iterations},
                      {"pem_converged", fit.pem.converged},
                      {"training_rms_residual_c", fit.pem.rms_residual_c},
                      {"training_paper_fit_percent", fit.pem.paper_fit_percent},
                      {"training_nrmse_fit_percent", fit.pem.nrmse_fit_percent}};
  if (fit.has_held_out) {
    j["held_out_paper_fit_percent"] = fit.held_out_paper_fit_percent;
    j["held_out_nrmse_fit_percent"] = fit.held_out_nrmse_fit_percent;
  }
  return j;
}

nlohmann::json to_json(const core::Calibration& c) {
  nlohmann::json modes = nlohmann::json::array();
  for (int i = 0; i < c.model.noise.modes(); ++i) {
    modes.push_back({{"offset_mm", c.model.noise.mean[i]},
                     {"std_mm", std::sqrt(c.model.noise.variance[i])},
                     {"weight", c.model.noise.weight[i]}});
  }
  return {{"thermal", thermal_json(c.thermal)},
          {"basis", c.model.basis.describe()},
          {"theta_mm",
           std::vector<double>(c.model.theta.data(), c.model.theta.data() + c.model.theta.size())},
          {"modes", modes},
          {"samples", c.provenance.samples},
          {"data_set", c.provenance.data_set}};
}

nlohmann::json to_json(const std::vector<calibration::WindowEvaluation>& evaluations) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& e : evaluations) {
    nlohmann::json j = {{"window", e.window}, {"windows", e.estimates.start.size()}};
    if (e.has_truth) {
      j["em"] = to_json(e.em);
      j["raw_mean"] = to_json(e.raw);
      j["bias_corrected_mean"] = to_json(e.bias_corrected);
      j["mae_improvement"] = e.raw.mean_absolute_error / e.em.mean_absolute_error;
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
  out += "  prediction-error fit:    " + thermal_line(fit.pem.parameters) + "\n";
  out += fmt::format(
      "  training fit: RMS {:.4f} °C, Eq. 26 {:.5f} %, NRMSE fit {:.2f} % ({} "
      "iterations{})\n",
      fit.pem.rms_residual_c, fit.pem.paper_fit_percent, fit.pem.nrmse_fit_percent,
      fit.pem.iterations, fit.pem.converged ? "" : ", not converged");
  if (fit.has_held_out) {
    out += fmt::format("  held-out fit: Eq. 26 {:.5f} % (paper: 92.79 %), NRMSE fit {:.2f} %\n",
                       fit.held_out_paper_fit_percent, fit.held_out_nrmse_fit_percent);
  }
  return out;
}

std::string calibration_text(const core::Calibration& c) {
  std::string out = "measurement model (Eq. 8): basis " + c.model.basis.describe() + "\n";
  for (int i = 0; i < c.model.noise.modes(); ++i) {
    out += fmt::format("  mode {}: offset {:+.3f} mm, std {:.3f} mm, weight {:.3f}\n", i + 1,
                       c.model.noise.mean[i], std::sqrt(c.model.noise.variance[i]),
                       c.model.noise.weight[i]);
  }
  return out;
}

std::string window_table_text(const std::vector<calibration::WindowEvaluation>& evaluations) {
  std::string out;
  out += fmt::format("{:>7} {:>8}  {:<22} {:>9} {:>9} {:>11} {:>9}\n", "window", "windows",
                     "estimator", "ME mm", "MAE mm", "var|e| mm2", "RMSE mm");
  for (const auto& e : evaluations) {
    if (!e.has_truth) {
      out += fmt::format("{:>7} {:>8}  (no true distance in the data: no errors)\n", e.window,
                         e.estimates.start.size());
      continue;
    }
    const std::pair<const char*, const core::ErrorMoments*> rows[] = {
        {"raw mean (y bar)", &e.raw},
        {"mean of y - H theta", &e.bias_corrected},
        {"EM d hat", &e.em}};
    for (const auto& [name, m] : rows) {
      out += fmt::format("{:>7} {:>8}  {:<22} {:>9.3f} {:>9.3f} {:>11.3f} {:>9.3f}\n", e.window,
                         e.estimates.start.size(), name, m->mean_error, m->mean_absolute_error,
                         m->absolute_error_variance, m->rmse);
    }
    out += fmt::format("{:>7} {:>8}  MAE raw / MAE EM = {:.2f}\n", e.window, "",
                       e.raw.mean_absolute_error / e.em.mean_absolute_error);
  }
  return out;
}

}  // namespace tofcomp::cli
