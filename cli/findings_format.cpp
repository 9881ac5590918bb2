#include "cli/findings_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/effect_grammar.hpp"

namespace tofcomp::cli {
namespace {

bool any_significant(const core::Diagnosis& d) {
  return !d.findings.empty() && d.findings.front().significant;
}

// The term of the grammar whose effect a residual test looks for.
nlohmann::json search_effect(core::EffectKind kind) {
  using core::Covariate;
  using core::Parameter;
  const auto name = [](Parameter p, Covariate c) {
    return nlohmann::json(core::effect_name(core::EffectLabel{p, c}));
  };
  switch (kind) {
    case core::EffectKind::ModePersistence:
      return name(Parameter::Markov, Covariate::None);
    case core::EffectKind::TemperatureDependentWeights:
      return name(Parameter::Weights, Covariate::JunctionTemperature);
    case core::EffectKind::TemperatureDependentSpread:
      return name(Parameter::Spread, Covariate::JunctionTemperature);
    case core::EffectKind::Outliers:
      return name(Parameter::Outliers, Covariate::None);
    case core::EffectKind::HeatingHysteresis:
      return name(Parameter::Bias, Covariate::HeatingRate);
    case core::EffectKind::TimeDrift:
      return name(Parameter::Bias, Covariate::Time);
    case core::EffectKind::WarmUp:
      return name(Parameter::Bias, Covariate::TimeSincePowerOn);
    case core::EffectKind::ExtraMode:
      return name(Parameter::ExtraMode, Covariate::None);
    case core::EffectKind::SerialDependence:
      break;
  }
  return nullptr;
}

}  // namespace

nlohmann::json to_json(const core::Diagnosis& d) {
  const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; };
  nlohmann::json out = nlohmann::json::array();
  for (const auto& f : d.findings) {
    nlohmann::json finding = {{"effect", core::effect_name(f.kind)},
                              {"test", f.test},
                              {"covariate", f.covariate},
                              {"statistic", f.result.statistic},
                              {"p_value", f.result.p_value},
                              {"z", f.result.z},
                              {"significant", f.significant},
                              {"search_effect", search_effect(f.kind)},
                              {"reference", f.reference},
                              {"null_mean", number(f.null_mean)},
                              {"null_std", number(f.null_std)},
                              {"textbook_p_value", f.textbook_p_value}};
    if (f.kind == core::EffectKind::Outliers) {
      finding["mode_scale_mm"] = std::vector<double>(
          d.mode_scale_mm.data(), d.mode_scale_mm.data() + d.mode_scale_mm.size());
      finding["lasing_modes"] = d.lasing_modes;
      finding["resolution_mm"] = d.resolution_mm;
    }
    out.push_back(std::move(finding));
  }
  return out;
}

namespace {

// The statistic under the trained model: "256 ± 23" (the draws'), an expected count, or "-".
std::string under_the_model(const core::Finding& f) {
  if (std::isfinite(f.null_mean) && std::isfinite(f.null_std)) {
    return fmt::format("{:.4g} ± {:.2g}", f.null_mean, f.null_std);
  }
  if (std::isfinite(f.null_mean)) return fmt::format("{:.3g}", f.null_mean);
  return "-";
}

// The references the table's p-values came from, each once, in the table's order.
std::string references(const core::Diagnosis& d) {
  std::vector<std::string> seen;
  for (const auto& f : d.findings) {
    if (std::find(seen.begin(), seen.end(), f.reference) == seen.end()) {
      seen.push_back(f.reference);
    }
  }
  std::string text;
  for (const auto& r : seen) text += (text.empty() ? "" : "; ") + r;
  return text;
}

}  // namespace

std::string diagnosis_text(const core::Diagnosis& d) {
  std::string text =
      fmt::format("{:<36} {:<24} {:<36} {:>12} {:>20} {:>10} {:>8}\n", "effect", "test",
                  "against", "statistic", "under the model", "p-value", "z");
  for (const auto& f : d.findings) {
    text += fmt::format("{:<36} {:<24} {:<36} {:>12.4g} {:>20} {:>10.3g} {:>8.2f}{}\n",
                        core::effect_name(f.kind), f.test, f.covariate, f.result.statistic,
                        under_the_model(f), f.result.p_value, f.result.z,
                        f.significant ? "  *" : "");
  }
  text += "p-values against " + references(d) +
          " (the ranges' rounding moves the statistics from their textbook laws even where the "
          "model holds: docs/closing-the-loop.md, section 4.1)\n";
  text += any_significant(d)
              ? "* significant at 5 % family-wise (Bonferroni) on the whole record; evidence, "
                "not the verdict: the model search above names and keeps\n"
              : "no test is significant at 5 % family-wise on the whole record\n";
  return text;
}

}  // namespace tofcomp::cli
