#include "cli/findings_format.hpp"

#include <fmt/format.h>

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
  nlohmann::json out = nlohmann::json::array();
  for (const auto& f : d.findings) {
    out.push_back({{"effect", core::effect_name(f.kind)},
                   {"test", f.test},
                   {"covariate", f.covariate},
                   {"statistic", f.result.statistic},
                   {"p_value", f.result.p_value},
                   {"z", f.result.z},
                   {"significant", f.significant},
                   {"search_effect", search_effect(f.kind)}});
  }
  return out;
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
              ? "* significant at 5 % family-wise (Bonferroni) on the whole record; evidence, "
                "not the verdict: the model search above names and keeps\n"
              : "no test is significant at 5 % family-wise on the whole record\n";
  return text;
}

}  // namespace tofcomp::cli
