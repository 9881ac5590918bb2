#include "io/extension_yaml.hpp"

#include <cmath>
#include <string>

namespace tofcomp::io {
namespace {

void emit_term(YAML::Emitter& out, const core::Term& t) {
  out << YAML::Key << "parameter" << YAML::Value << core::parameter_token(t.parameter);
  if (t.parameter == core::Parameter::ModeOffset) out << YAML::Key << "mode" << YAML::Value << t.mode + 1;
  out << YAML::Key << "covariate" << YAML::Value << core::covariate_token(t.covariate);
  out << YAML::Key << "form" << YAML::Value << core::form_token(t.form);
  if (t.needs_time_constant()) {
    out << YAML::Key << "time_constant_s" << YAML::Value << t.time_constant_s;
  }
  if (t.form == core::Form::Linear) {
    out << YAML::Key << "centre" << YAML::Value << t.centre;
    out << YAML::Key << "scale" << YAML::Value << t.scale;
    if (t.has_covariate_range()) {
      emit_vector(out, "covariate_range",
                  Eigen::Vector2d(t.covariate_low, t.covariate_high));
    }
  }
  if (t.knots.size() > 0) emit_vector(out, t.is_noise_term() ? "edges" : "knots", t.knots);
}

core::Term read_term(const YamlMap& x) {
  core::Term t;
  try {
    t.parameter = core::parse_parameter(x.text("parameter"));
    t.covariate = core::parse_covariate(x.text_or("covariate", "none"));
    t.form = core::parse_form(x.text_or("form", "none"));
  } catch (const core::InvalidInput& e) {
    x.fail("parameter", e.what());
  }
  if (t.parameter == core::Parameter::ModeOffset) {
    t.mode = static_cast<int>(x.integer("mode")) - 1;
  } else if (x.has("mode")) {
    x.fail("mode", "belongs to a mode_offset term only");
  }
  t.time_constant_s = x.number_or("time_constant_s", 0.0);
  t.centre = x.number_or("centre", 0.0);
  t.scale = x.number_or("scale", 1.0);
  if (x.has("covariate_range")) {
    const Eigen::VectorXd range = read_vector(x, "covariate_range");
    if (range.size() != 2 || !range.allFinite()) {
      x.fail("covariate_range", "must be two finite numbers, low and high");
    }
    t.covariate_low = range[0];
    t.covariate_high = range[1];
  }
  if (x.has("knots")) t.knots = read_vector(x, "knots");
  if (x.has("edges")) t.knots = read_vector(x, "edges");
  try {
    t.validate();
  } catch (const core::InvalidInput& e) {
    x.fail("form", e.what());
  }
  return t;
}

// Bins write their table; a parametric term (linear, decay) its intercepts and slopes, from which
// the reader computes the table again.
void emit_bins(YAML::Emitter& out, const char* key, const char* table_key,
               const core::NoiseBins& bins) {
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  emit_term(out, bins.term);
  if (bins.term.is_parametric_noise()) {
    emit_vector(out, "intercept", bins.intercept);
    emit_vector(out, "slope", bins.slope);
  } else {
    emit_matrix(out, table_key, bins.table);
  }
  out << YAML::EndMap;
}

core::NoiseBins read_bins(const YamlMap& x, std::string_view key, const char* table_key) {
  const YamlMap b(x.node(key), x.child_path(key),
                  {"parameter", "covariate", "form", "time_constant_s", "centre", "scale", "edges",
                   "intercept", "slope", table_key});
  core::NoiseBins bins;
  bins.term = read_term(b);
  if (bins.term.is_parametric_noise()) {
    bins.intercept = read_vector(b, "intercept");
    bins.slope = read_vector(b, "slope");
    if (bins.intercept.size() != bins.slope.size()) b.fail("slope", "must be as long as intercept");
    bins.refresh_table();
  } else {
    bins.table = read_matrix(b, table_key);
    if (bins.table.size() == 0) b.fail(table_key, "is required");
  }
  return bins;
}

// The outlier component, when the extension has one (both versions write it alike).
void read_outliers(const YamlMap& x, core::ExtendedMixture& m) {
  if (!x.has("outlier_weight")) return;
  m.outlier_weight = x.number("outlier_weight");
  const double span = x.number("outlier_span_mm");
  if (!(span > 0.0)) x.fail("outlier_span_mm", "must be positive");
  m.outlier_density = 1.0 / span;
}

// Version 1: one effect; its covariate term and its bins on the junction temperature.
core::ModelExtension read_version_1(const YamlMap& top, const core::MixtureParameters& modes) {
  const YamlMap x(
      top.node("extension"), "extension",
      {"effect", "covariate", "covariate_mm", "time_constant_s", "bin_edges_c", "bin_weights",
       "bin_variances_mm2", "transition", "outlier_weight", "outlier_span_mm"});
  using core::Covariate;
  using core::Form;
  using core::Parameter;
  struct Effect {
    const char* token;
    Parameter parameter;
    Covariate covariate;
  };
  constexpr Effect kEffects[] = {
      {"mode_persistence", Parameter::Markov, Covariate::None},
      {"temperature_dependent_weights", Parameter::Weights, Covariate::JunctionTemperature},
      {"temperature_dependent_spread", Parameter::Spread, Covariate::JunctionTemperature},
      {"outliers", Parameter::Outliers, Covariate::None},
      {"heating_hysteresis", Parameter::Bias, Covariate::HeatingRate},
      {"time_drift", Parameter::Bias, Covariate::Time},
      {"warm_up_after_power_on", Parameter::Bias, Covariate::TimeSincePowerOn},
      {"one_more_lasing_mode", Parameter::ExtraMode, Covariate::None}};
  core::ModelExtension e;
  const std::string effect = x.text("effect");
  const Effect* found = nullptr;
  for (const Effect& k : kEffects) {
    if (effect == k.token) found = &k;
  }
  if (!found) x.fail("effect", "'" + effect + "' is not an effect with an extension");
  e.effects.push_back({found->parameter, found->covariate});
  e.extended_mixture.modes = modes;
  const std::string covariate = x.text_or("covariate", "none");
  if (covariate != "none") {
    core::Term t;
    t.parameter = Parameter::Bias;
    // The old covariates were the raw values: hours, °C/min, exp(−t_on/τ).
    if (covariate == "time_h") {
      t.covariate = Covariate::Time, t.form = Form::Linear;
    } else if (covariate == "heating_rate_c_per_min") {
      t.covariate = Covariate::HeatingRate, t.form = Form::Linear;
    } else if (covariate == "warm_up") {
      t.covariate = Covariate::TimeSincePowerOn, t.form = Form::Decay;
      t.time_constant_s = x.number("time_constant_s");
      if (!(t.time_constant_s > 0.0)) x.fail("time_constant_s", "must be positive");
    } else {
      x.fail("covariate", "must be none, time_h, heating_rate_c_per_min or warm_up");
    }
    e.mean_terms.push_back({t, Eigen::VectorXd::Constant(1, x.number_or("covariate_mm", 0.0))});
  }
  const auto bins = [&](Parameter p, const char* key) -> std::optional<core::NoiseBins> {
    if (!x.has(key)) return std::nullopt;
    core::NoiseBins b;
    b.term.parameter = p;
    b.term.covariate = Covariate::JunctionTemperature;
    b.term.form = Form::Bins;
    b.term.knots = read_vector(x, "bin_edges_c");
    b.table = read_matrix(x, key);
    return b;
  };
  e.extended_mixture.weight_bins = bins(Parameter::Weights, "bin_weights");
  e.extended_mixture.variance_bins = bins(Parameter::Spread, "bin_variances_mm2");
  e.extended_mixture.transition = read_matrix(x, "transition");
  read_outliers(x, e.extended_mixture);
  return e;
}

core::ModelExtension read_version_2(const YamlMap& top, const core::MixtureParameters& modes) {
  const YamlMap x(top.node("extension"), "extension",
                  {"effects", "terms", "weight_bins", "spread_bins", "transition",
                   "outlier_weight", "outlier_span_mm"});
  core::ModelExtension e;
  const YAML::Node effects = x.node("effects");
  if (!effects.IsSequence() || effects.size() == 0) x.fail("effects", "must be a non-empty list");
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const YamlMap effect(effects[i], x.child_path("effects") + "[" + std::to_string(i) + "]",
                         {"parameter", "covariate"});
    try {
      e.effects.push_back({core::parse_parameter(effect.text("parameter")),
                           core::parse_covariate(effect.text("covariate"))});
    } catch (const core::InvalidInput& error) {
      effect.fail("parameter", error.what());
    }
  }
  if (x.has("terms")) {
    const YAML::Node terms = x.node("terms");
    if (!terms.IsSequence()) x.fail("terms", "must be a list");
    for (std::size_t i = 0; i < terms.size(); ++i) {
      const YamlMap t(terms[i], x.child_path("terms") + "[" + std::to_string(i) + "]",
                      {"parameter", "mode", "covariate", "form", "time_constant_s", "centre",
                       "scale", "covariate_range", "knots", "coefficients_mm"});
      e.mean_terms.push_back({read_term(t), read_vector(t, "coefficients_mm")});
    }
  }
  e.extended_mixture.modes = modes;
  if (x.has("weight_bins")) e.extended_mixture.weight_bins = read_bins(x, "weight_bins", "weights");
  if (x.has("spread_bins")) {
    e.extended_mixture.variance_bins = read_bins(x, "spread_bins", "variances_mm2");
  }
  e.extended_mixture.transition = read_matrix(x, "transition");
  read_outliers(x, e.extended_mixture);
  return e;
}

}  // namespace

void emit_extension(YAML::Emitter& out, const core::ModelExtension& e,
                    const core::MixtureParameters& modes) {
  e.validate();
  if (e.extended_mixture.modes.mean != modes.mean ||
      e.extended_mixture.modes.variance != modes.variance ||
      e.extended_mixture.modes.weight != modes.weight) {
    throw core::InvalidInput("the extension's modes differ from the measurement's modes");
  }
  out << YAML::Key << "extension" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "effects" << YAML::Value << YAML::BeginSeq;
  for (const core::EffectLabel& label : e.effects) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "parameter" << YAML::Value << core::parameter_token(label.parameter);
    out << YAML::Key << "covariate" << YAML::Value << core::covariate_token(label.covariate);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (!e.mean_terms.empty()) {
    out << YAML::Key << "terms" << YAML::Value << YAML::BeginSeq;
    for (const core::MeanTermFit& t : e.mean_terms) {
      out << YAML::BeginMap;
      emit_term(out, t.term);
      emit_vector(out, "coefficients_mm", t.coefficients);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  const core::ExtendedMixture& m = e.extended_mixture;
  if (m.weight_bins) emit_bins(out, "weight_bins", "weights", *m.weight_bins);
  if (m.variance_bins) emit_bins(out, "spread_bins", "variances_mm2", *m.variance_bins);
  emit_matrix(out, "transition", m.transition);
  if (m.outlier_weight > 0.0) {
    out << YAML::Key << "outlier_weight" << YAML::Value << m.outlier_weight;
    out << YAML::Key << "outlier_span_mm" << YAML::Value << 1.0 / m.outlier_density;
  }
  out << YAML::EndMap;
}

core::ModelExtension read_extension(const YamlMap& top, const core::MixtureParameters& modes,
                                    long version) {
  core::ModelExtension e = version == 1 ? read_version_1(top, modes) : read_version_2(top, modes);
  try {
    e.validate();
  } catch (const core::InvalidInput& error) {
    throw YamlSchemaError(std::string("extension: ") + error.what());
  }
  return e;
}

Eigen::VectorXd read_vector(const YamlMap& parent, std::string_view key) {
  const YAML::Node list = parent.node(key);
  if (!list.IsSequence()) parent.fail(key, "must be a list of numbers");
  Eigen::VectorXd v(static_cast<Eigen::Index>(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i) {
    double x = 0.0;
    if (!list[i].IsScalar() || !YAML::convert<double>::decode(list[i], x) || !std::isfinite(x)) {
      parent.fail(std::string(key) + "[" + std::to_string(i) + "]", "must be a finite number");
    }
    v[static_cast<Eigen::Index>(i)] = x;
  }
  return v;
}

Eigen::MatrixXd read_matrix(const YamlMap& parent, std::string_view key) {
  if (!parent.has(key)) return {};
  const YAML::Node rows = parent.node(key);
  if (!rows.IsSequence() || rows.size() == 0) parent.fail(key, "must be a non-empty list of lists");
  Eigen::MatrixXd m;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const YAML::Node row = rows[r];
    const std::string where = std::string(key) + "[" + std::to_string(r) + "]";
    if (!row.IsSequence() || (r > 0 && static_cast<Eigen::Index>(row.size()) != m.cols())) {
      parent.fail(where, "must be a list of numbers as long as the first row");
    }
    if (r == 0) {
      m.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(row.size()));
    }
    for (std::size_t c = 0; c < row.size(); ++c) {
      double x = 0.0;
      if (!row[c].IsScalar() || !YAML::convert<double>::decode(row[c], x) || !std::isfinite(x)) {
        parent.fail(where + "[" + std::to_string(c) + "]", "must be a finite number");
      }
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = x;
    }
  }
  return m;
}

void emit_vector(YAML::Emitter& out, const char* key, const Eigen::VectorXd& v) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (Eigen::Index i = 0; i < v.size(); ++i) out << v[i];
  out << YAML::EndSeq;
}

void emit_matrix(YAML::Emitter& out, const char* key, const Eigen::MatrixXd& m) {
  if (m.size() == 0) return;
  out << YAML::Key << key << YAML::Value << YAML::BeginSeq;
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    out << YAML::Flow << YAML::BeginSeq;
    for (Eigen::Index c = 0; c < m.cols(); ++c) out << m(r, c);
    out << YAML::EndSeq;
  }
  out << YAML::EndSeq;
}

}  // namespace tofcomp::io
