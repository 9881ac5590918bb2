#include "cli/extension_format.hpp"

#include <fmt/format.h>

#include "cli/report_format.hpp"

namespace tofcomp::cli {
namespace {

bool any_significant(const core::Diagnosis& d) {
  return !d.findings.empty() && d.findings.front().significant;
}

}  // namespace

nlohmann::json to_json(const core::Diagnosis& d) {
  nlohmann::json out;
  out["findings"] = nlohmann::json::array();
  for (const auto& f : d.findings) {
    out["findings"].push_back({{"effect", core::effect_name(f.kind)},
                               {"test", f.test},
                               {"covariate", f.covariate},
                               {"statistic", f.result.statistic},
                               {"p_value", f.result.p_value},
                               {"z", f.result.z},
                               {"significant", f.significant}});
  }
  out["named"] = any_significant(d) ? core::effect_name(d.findings.front().kind) : "none";
  return out;
}

nlohmann::json to_json(const calibration::ExtensionReport& e) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const auto& [name, value] : e.parameters) parameters[name] = value;
  nlohmann::json errors = nlohmann::json::array();
  for (const auto& w : e.errors) {
    errors.push_back({{"window", w.window},
                      {"before", to_json(w.before)},
                      {"after", to_json(w.after)},
                      {"mae_factor", w.before.mean_absolute_error / w.after.mean_absolute_error},
                      {"cramer_rao_mae_mm", w.cramer_rao_mae_mm}});
  }
  return {{"effect", core::effect_name(e.effect)},
          {"named", core::effect_name(e.named)},
          {"model", e.model},
          {"parameters", parameters},
          {"held_out_log_likelihood_before", e.held_out_log_likelihood_before},
          {"held_out_log_likelihood_after", e.held_out_log_likelihood_after},
          {"held_out_log_likelihood_gain", e.held_out_log_likelihood_gain()},
          {"mae_factor", e.mean_absolute_error_factor()},
          {"kept", e.kept},
          {"errors", errors}};
}

std::string diagnosis_text(const core::Diagnosis& d) {
  std::string text = fmt::format("{:<36} {:<24} {:<36} {:>12} {:>10} {:>8}\n", "effect", "test",
                                 "against", "statistic", "p-value", "z");
  for (const auto& f : d.findings) {
    text += fmt::format("{:<36} {:<24} {:<36} {:>12.4g} {:>10.3g} {:>8.2f}{}\n",
                        core::effect_name(f.kind), f.test, f.covariate, f.result.statistic,
                        f.result.p_value, f.result.z, f.significant ? "  *" : "");
  }
  text += any_significant(d)
              ? fmt::format("* significant at 5 % family-wise (Bonferroni); the model lacks: {}\n",
                            core::effect_name(d.findings.front().kind))
              : "no finding is significant at 5 % family-wise: the model explains the data\n";
  return text;
}

std::string extension_text(const calibration::ExtensionReport& e) {
  std::string text = fmt::format("extension for {}: {}\n", core::effect_name(e.named), e.model);
  for (const auto& [name, value] : e.parameters)
    text += fmt::format("  {:<32} {:>12.5g}\n", name, value);
  text += fmt::format(
      "held-out log-likelihood of y - d: {:.1f} -> {:.1f} (gain {:.1f})\n"
      "held-out error of d hat (mm), the paper's model -> extended:\n"
      "{:>7} {:>16} {:>16} {:>16} {:>18} {:>8}\n",
      e.held_out_log_likelihood_before, e.held_out_log_likelihood_after,
      e.held_out_log_likelihood_gain(), "window", "mean error", "MAE", "RMSE", "var |e| (mm2)",
      "factor");
  for (const auto& w : e.errors) {
    text += fmt::format(
        "{:>7} {:>7.3f} {:>8.3f} {:>7.3f} {:>8.3f} {:>7.3f} {:>8.3f} {:>8.4f} {:>9.4f} {:>8.2f}\n",
        w.window, w.before.mean_error, w.after.mean_error, w.before.mean_absolute_error,
        w.after.mean_absolute_error, w.before.rmse, w.after.rmse, w.before.absolute_error_variance,
        w.after.absolute_error_variance,
        w.before.mean_absolute_error / w.after.mean_absolute_error);
  }
  for (const auto& w : e.errors) {
    text += fmt::format(
        "{:>7} Cramér–Rao bound {:.3f} mm (the paper's modes): MAE / bound {:.2f} -> {:.2f}\n",
        w.window, w.cramer_rao_mae_mm, w.before.mean_absolute_error / w.cramer_rao_mae_mm,
        w.after.mean_absolute_error / w.cramer_rao_mae_mm);
  }
  text += e.kept ? fmt::format("kept: held-out MAE of d hat cut by a factor {:.2f}\n",
                               e.mean_absolute_error_factor())
                 : fmt::format(
                       "not kept: held-out log-likelihood gain {:.1f}, MAE of d hat factor {:.3f} "
                       "(kept when the gain is positive and the factor at least {:.2f})\n",
                       e.held_out_log_likelihood_gain(), e.mean_absolute_error_factor(),
                       calibration::kMinimumMaeFactor);
  return text;
}

}  // namespace tofcomp::cli
