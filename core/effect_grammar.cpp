#include "core/effect_grammar.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

template <typename Enum, std::size_t N>
Enum parse_token(const std::string& token, const std::array<Enum, N>& values,
                 const char* (*token_of)(Enum), const char* what) {
  for (const Enum v : values) {
    if (token == token_of(v)) return v;
  }
  std::string known;
  for (const Enum v : values) known += std::string(known.empty() ? "" : ", ") + token_of(v);
  throw InvalidInput("'" + token + "' is not a " + what + " (one of: " + known + ")");
}

constexpr std::array<Parameter, 7> kParameters{
    Parameter::Bias,   Parameter::ModeOffset, Parameter::Spread,  Parameter::Weights,
    Parameter::Markov, Parameter::ExtraMode,  Parameter::Outliers};
constexpr std::array<Covariate, 7> kCovariatesAndNone{
    Covariate::None,          Covariate::JunctionTemperature, Covariate::HeatingRate,
    Covariate::TimeSincePowerOn, Covariate::Time,             Covariate::Ambient,
    Covariate::JunctionLag};
constexpr std::array<Form, 5> kForms{Form::None, Form::Linear, Form::Smooth, Form::Decay,
                                     Form::Bins};

// How a covariate reads in a sentence: "the time since power-on".
const char* covariate_phrase(Covariate c) {
  switch (c) {
    case Covariate::None:
      return "nothing";
    case Covariate::JunctionTemperature:
      return "the junction temperature";
    case Covariate::HeatingRate:
      return "the heating rate";
    case Covariate::TimeSincePowerOn:
      return "the time since power-on";
    case Covariate::Time:
      return "time";
    case Covariate::Ambient:
      return "the ambient temperature";
    case Covariate::JunctionLag:
      return "the junction's lag";
  }
  return "?";
}

bool structural(Parameter p) {
  return p == Parameter::Markov || p == Parameter::ExtraMode || p == Parameter::Outliers;
}

}  // namespace

const char* parameter_token(Parameter p) {
  switch (p) {
    case Parameter::Bias:
      return "bias";
    case Parameter::ModeOffset:
      return "mode_offset";
    case Parameter::Spread:
      return "spread";
    case Parameter::Weights:
      return "weights";
    case Parameter::Markov:
      return "markov";
    case Parameter::ExtraMode:
      return "extra_mode";
    case Parameter::Outliers:
      return "outliers";
  }
  return "?";
}

const char* covariate_token(Covariate c) {
  switch (c) {
    case Covariate::None:
      return "none";
    case Covariate::JunctionTemperature:
      return "junction_temperature";
    case Covariate::HeatingRate:
      return "heating_rate";
    case Covariate::TimeSincePowerOn:
      return "time_since_power_on";
    case Covariate::Time:
      return "time";
    case Covariate::Ambient:
      return "ambient";
    case Covariate::JunctionLag:
      return "junction_lag";
  }
  return "?";
}

const char* form_token(Form f) {
  switch (f) {
    case Form::None:
      return "none";
    case Form::Linear:
      return "linear";
    case Form::Smooth:
      return "smooth";
    case Form::Decay:
      return "decay";
    case Form::Bins:
      return "bins";
  }
  return "?";
}

Parameter parse_parameter(const std::string& token) {
  return parse_token(token, kParameters, parameter_token, "parameter of Eq. 8");
}
Covariate parse_covariate(const std::string& token) {
  return parse_token(token, kCovariatesAndNone, covariate_token, "covariate");
}
Form parse_form(const std::string& token) {
  return parse_token(token, kForms, form_token, "form");
}

const char* covariate_unit(Covariate c) {
  switch (c) {
    case Covariate::JunctionTemperature:
    case Covariate::Ambient:
    case Covariate::JunctionLag:
      return "°C";
    case Covariate::HeatingRate:
      return "°C/min";
    case Covariate::TimeSincePowerOn:
      return "s";
    case Covariate::Time:
      return "h";
    case Covariate::None:
      break;
  }
  return "";
}

std::string label_parameter_token(const EffectLabel& label) {
  if (label.parameter == Parameter::Bias && label.covariate == Covariate::JunctionLag) {
    return "thermal_state";
  }
  return parameter_token(label.parameter);
}

std::string label_covariate_token(const EffectLabel& label) {
  if (label.covariate == Covariate::JunctionLag) return "none";
  return covariate_token(label.covariate);
}

std::string effect_name(const EffectLabel& label) {
  const Covariate c = label.covariate;
  switch (label.parameter) {
    case Parameter::Markov:
      return "mode persistence";
    case Parameter::ExtraMode:
      return "one more lasing mode";
    case Parameter::Outliers:
      return "outliers";
    case Parameter::Bias:
      if (c == Covariate::Time) return "time drift";
      if (c == Covariate::TimeSincePowerOn) return "warm-up after power-on";
      if (c == Covariate::HeatingRate) return "heating hysteresis";
      if (c == Covariate::Ambient) return "ambient-dependent bias";
      if (c == Covariate::JunctionLag) return "another thermal state";
      return std::string("the bias depends on ") + covariate_phrase(c);
    case Parameter::ModeOffset:
      if (c == Covariate::JunctionTemperature) return "temperature-dependent mode offset";
      return std::string("a mode's offset depends on ") + covariate_phrase(c);
    case Parameter::Spread:
      if (c == Covariate::JunctionTemperature) return "temperature-dependent spread";
      return std::string("the spread depends on ") + covariate_phrase(c);
    case Parameter::Weights:
      if (c == Covariate::JunctionTemperature) return "temperature-dependent weights";
      return std::string("the weights depend on ") + covariate_phrase(c);
  }
  return "?";
}

int Term::columns() const {
  if (!is_mean_term()) return 0;
  return form == Form::Smooth ? static_cast<int>(knots.size()) - 1 : 1;
}

std::string Term::describe() const {
  if (structural(parameter)) return parameter_token(parameter);
  std::ostringstream out;
  if (parameter == Parameter::ModeOffset) {
    out << "mode " << mode + 1 << " offset";
  } else {
    out << parameter_token(parameter);
  }
  out << " x " << covariate_token(covariate) << " (" << form_token(form);
  if (needs_time_constant()) out << ", tau = " << std::lround(time_constant_s) << " s";
  if (form == Form::Smooth) out << ", " << knots.size() << " knots";
  out << ")";
  return out.str();
}

void Term::validate() const {
  const auto fail = [&](const std::string& why) {
    throw InvalidInput("term " + describe() + ": " + why);
  };
  if (structural(parameter)) {
    if (covariate != Covariate::None || form != Form::None) fail("a structure takes no covariate");
    return;
  }
  if (covariate == Covariate::None) fail("needs a covariate");
  const bool mean = is_mean_term();
  if (mean && form == Form::Bins) fail("a bias or offset term takes linear, smooth or decay");
  if (!mean && form == Form::Smooth) fail("a spread or weights term takes bins, linear or decay");
  if (form == Form::None) fail("needs a form");
  if (form == Form::Decay && covariate != Covariate::TimeSincePowerOn &&
      covariate != Covariate::Time) {
    fail("a decay needs a covariate that counts time from zero");
  }
  if (parameter == Parameter::ModeOffset && mode < 0) fail("names no mode");
  if (needs_time_constant() && !(time_constant_s > 0.0 && std::isfinite(time_constant_s))) {
    fail("needs a positive time constant");
  }
  if (form == Form::Linear && !(scale > 0.0 && std::isfinite(scale) && std::isfinite(centre))) {
    fail("needs a finite centre and a positive scale");
  }
  if (!(covariate_low <= covariate_high) || covariate_low == kInfinity ||
      covariate_high == -kInfinity) {
    fail("needs a covariate range whose low end is not above its high end");
  }
  if (form == Form::Smooth && (knots.size() < kMinSmoothKnots || knots.size() > kMaxSmoothKnots)) {
    fail("needs " + std::to_string(kMinSmoothKnots) + " to " + std::to_string(kMaxSmoothKnots) +
         " knots, has " + std::to_string(knots.size()));
  }
  if (form == Form::Bins && knots.size() < 1) fail("needs at least one bin edge");
  if (is_parametric_noise() && knots.size() != kNoiseLevels - 1) {
    fail("needs the " + std::to_string(kNoiseLevels - 1) + " edges of its levels");
  }
  for (Eigen::Index i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i]) || (i > 0 && !(knots[i] > knots[i - 1]))) {
      fail("knots must be finite and increasing");
    }
  }
}

}  // namespace tofcomp::core
