#include "sim/scenario_yaml.hpp"

#include <filesystem>
#include <functional>

#include "io/yaml_fields.hpp"

namespace tofcomp::sim {
namespace {

using io::YamlMap;

core::ThermalParameters read_thermal(const YamlMap& parent) {
  const YamlMap m(parent.node("thermal"), parent.child_path("thermal"),
                  {"r1_k_per_w", "r2_k_per_w", "c1_j_per_k", "c2_j_per_k", "power_w"});
  core::ThermalParameters p;
  p.r1_k_per_w = m.number("r1_k_per_w");
  p.r2_k_per_w = m.number("r2_k_per_w");
  p.c1_j_per_k = m.number("c1_j_per_k");
  p.c2_j_per_k = m.number("c2_j_per_k");
  p.power_w = m.number("power_w");
  return p;
}

std::vector<PowerSegment> read_power(const YamlMap& parent) {
  const YamlMap m(parent.node("power"), parent.child_path("power"), {"segments", "repeat"});
  const YAML::Node list = m.node("segments");
  if (!list.IsSequence() || list.size() == 0) m.fail("segments", "must be a non-empty list");
  const long repeat = m.integer_or("repeat", 1);
  if (repeat < 1) m.fail("repeat", "must be at least 1");
  std::vector<PowerSegment> once;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlMap s(list[i], m.child_path("segments") + "[" + std::to_string(i) + "]",
                    {"on", "duration_s"});
    once.push_back({s.boolean("on"), s.number("duration_s")});
  }
  std::vector<PowerSegment> all;
  for (long r = 0; r < repeat; ++r) all.insert(all.end(), once.begin(), once.end());
  return all;
}

AmbientProfile read_ambient(const YamlMap& parent) {
  AmbientProfile a;
  if (!parent.has("ambient")) return a;
  const YamlMap m(parent.node("ambient"), parent.child_path("ambient"),
                  {"base_c", "drift_c_per_hour", "steps"});
  a.base_c = m.number_or("base_c", a.base_c);
  a.drift_c_per_hour = m.number_or("drift_c_per_hour", 0.0);
  if (m.has("steps")) {
    const YAML::Node list = m.node("steps");
    if (!list.IsSequence()) m.fail("steps", "must be a list");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const YamlMap s(list[i], m.child_path("steps") + "[" + std::to_string(i) + "]",
                      {"time_s", "change_c"});
      a.steps.push_back({s.number("time_s"), s.number("change_c")});
    }
  }
  return a;
}

CaseSensor read_sensor(const YamlMap& parent) {
  CaseSensor s;
  if (!parent.has("sensor")) return s;
  const YamlMap m(parent.node("sensor"), parent.child_path("sensor"),
                  {"period_s", "noise_std_c", "resolution_c"});
  s.period_s = m.number_or("period_s", s.period_s);
  s.noise_std_c = m.number_or("noise_std_c", s.noise_std_c);
  s.resolution_c = m.number_or("resolution_c", s.resolution_c);
  return s;
}

RangeBias read_bias(const YamlMap& parent) {
  RangeBias b;
  if (!parent.has("bias")) return b;
  const YamlMap m(parent.node("bias"), parent.child_path("bias"),
                  {"reference_c", "slope_mm_per_c", "curvature_mm_per_c2", "knee_amplitude_mm",
                   "knee_width_c"});
  b.reference_c = m.number_or("reference_c", b.reference_c);
  b.slope_mm_per_c = m.number_or("slope_mm_per_c", b.slope_mm_per_c);
  b.curvature_mm_per_c2 = m.number_or("curvature_mm_per_c2", b.curvature_mm_per_c2);
  b.knee_amplitude_mm = m.number_or("knee_amplitude_mm", b.knee_amplitude_mm);
  b.knee_width_c = m.number_or("knee_width_c", b.knee_width_c);
  return b;
}

std::vector<LasingMode> read_modes(const YamlMap& parent) {
  const YAML::Node list = parent.node("modes");
  if (!list.IsSequence() || list.size() == 0) parent.fail("modes", "must be a non-empty list");
  std::vector<LasingMode> modes;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlMap m(list[i], parent.child_path("modes") + "[" + std::to_string(i) + "]",
                    {"offset_mm", "std_mm", "weight"});
    modes.push_back({m.number("offset_mm"), m.number("std_mm"), m.number("weight")});
  }
  return modes;
}

ScannerOutput read_scanner(const YamlMap& parent) {
  ScannerOutput s;
  if (!parent.has("scanner")) return s;
  const YamlMap m(parent.node("scanner"), parent.child_path("scanner"),
                  {"units", "max_range_mm", "beams", "field_deg", "scan_rate_hz"});
  const std::string units = m.text_or("units", "mm");
  if (units == "mm") {
    s.units = RangeUnits::Millimetre;
  } else if (units == "cm") {
    s.units = RangeUnits::Centimetre;
  } else {
    m.fail("units", "must be mm or cm, not '" + units + "'");
  }
  s.max_range_mm = m.number_or("max_range_mm", s.max_range_mm);
  s.beams = static_cast<int>(m.integer_or("beams", s.beams));
  s.field_deg = m.number_or("field_deg", s.field_deg);
  s.scan_rate_hz = m.number_or("scan_rate_hz", s.scan_rate_hz);
  return s;
}

// One optional effect: present → a sub-map with the effect's parameters (each defaulted).
template <typename Effect>
std::optional<Effect> read_effect(
    const YamlMap& effects, const char* key,
    std::initializer_list<std::pair<const char*, double Effect::*>> parameters) {
  if (!effects.has(key)) return std::nullopt;
  Effect effect;
  const YAML::Node node = effects.node(key);
  if (node.IsNull()) return effect;
  std::vector<std::string_view> names;
  for (const auto& p : parameters) names.emplace_back(p.first);
  const YamlMap m(node, effects.child_path(key), names);
  for (const auto& [name, field] : parameters) effect.*field = m.number_or(name, effect.*field);
  return effect;
}

TwinEffects read_effects(const YamlMap& parent) {
  TwinEffects fx;
  if (!parent.has("effects")) return fx;
  const YamlMap m(
      parent.node("effects"), parent.child_path("effects"),
      {"mode_persistence", "temperature_dependent_weights", "temperature_dependent_spread",
       "outliers", "heating_hysteresis", "time_drift", "warm_up"});
  fx.mode_persistence = read_effect<ModePersistence>(
      m, "mode_persistence", {{"stay_probability", &ModePersistence::stay_probability}});
  fx.temperature_dependent_weights = read_effect<TemperatureDependentWeights>(
      m, "temperature_dependent_weights",
      {{"log_odds_per_c", &TemperatureDependentWeights::log_odds_per_c}});
  fx.temperature_dependent_spread = read_effect<TemperatureDependentSpread>(
      m, "temperature_dependent_spread",
      {{"relative_per_c", &TemperatureDependentSpread::relative_per_c}});
  fx.outliers = read_effect<Outliers>(
      m, "outliers", {{"fraction", &Outliers::fraction}, {"spread_mm", &Outliers::spread_mm}});
  fx.heating_hysteresis = read_effect<HeatingHysteresis>(
      m, "heating_hysteresis", {{"mm_per_c_per_min", &HeatingHysteresis::mm_per_c_per_min}});
  fx.time_drift =
      read_effect<TimeDrift>(m, "time_drift", {{"mm_per_hour", &TimeDrift::mm_per_hour}});
  fx.warm_up = read_effect<WarmUp>(
      m, "warm_up",
      {{"amplitude_mm", &WarmUp::amplitude_mm}, {"time_constant_s", &WarmUp::time_constant_s}});
  return fx;
}

// `override` on top of `base`: mappings merge key by key, anything else replaces.
YAML::Node merged(const YAML::Node& base, const YAML::Node& override) {
  if (!base.IsMap() || !override.IsMap()) return YAML::Clone(override);
  YAML::Node out = YAML::Clone(base);
  for (const auto& entry : override) {
    const std::string key = entry.first.as<std::string>();
    out[key] = base[key] ? merged(base[key], entry.second) : YAML::Clone(entry.second);
  }
  return out;
}

YAML::Node load_with_base(const std::string& file, int depth);

// The scenario's document `root`, read from `file`, with its `base:` chain (paths relative to
// the file) applied.
YAML::Node with_base(YAML::Node root, const std::string& file, int depth) {
  constexpr int kMaxBaseDepth = 8;
  if (!root.IsMap() || !root["base"]) return root;
  if (depth >= kMaxBaseDepth) throw io::YamlSchemaError(file + ": base: chain is too deep");
  if (!root["base"].IsScalar()) throw io::YamlSchemaError(file + ": base must be a file name");
  const std::filesystem::path base_file =
      std::filesystem::path(file).parent_path() / root["base"].Scalar();
  YAML::Node own = YAML::Clone(root);
  own.remove("base");
  return merged(load_with_base(base_file.string(), depth + 1), own);
}

YAML::Node load_with_base(const std::string& file, int depth) {
  return with_base(io::load_yaml_file(file), file, depth);
}

// The scenario in the document `load` gives, read from `file`.
Scenario scenario_from(const std::function<YAML::Node()>& load, const std::string& file) {
  try {
    const YAML::Node root = load();
    const YamlMap m(root, "",
                    {"name", "seed", "thermal", "power", "ambient", "initial_case_c", "sensor",
                     "true_range_mm", "bias", "modes", "scanner", "range_period_s", "effects"});
    Scenario s;
    s.name = m.text_or("name", s.name);
    const long seed = m.integer_or("seed", 1);
    if (seed < 0) m.fail("seed", "must be non-negative");
    s.seed = static_cast<std::uint64_t>(seed);
    s.thermal = read_thermal(m);
    s.power = read_power(m);
    s.ambient = read_ambient(m);
    s.initial_case_c = m.number_or("initial_case_c", s.initial_case_c);
    s.sensor = read_sensor(m);
    s.true_range_mm = m.number_or("true_range_mm", s.true_range_mm);
    s.bias = read_bias(m);
    s.modes = read_modes(m);
    s.scanner = read_scanner(m);
    s.range_period_s = m.number_or("range_period_s", s.range_period_s);
    s.effects = read_effects(m);
    s.validate();
    return s;
  } catch (const io::YamlSchemaError& e) {
    const std::string what = e.what();
    if (what.rfind(file, 0) == 0) throw;
    throw io::YamlSchemaError(file + ": " + what);
  } catch (const core::InvalidInput& e) {
    throw io::YamlSchemaError(file + ": " + e.what());
  }
}

}  // namespace

Scenario load_scenario_file(const std::string& file) {
  return scenario_from([&] { return load_with_base(file, 0); }, file);
}

Scenario parse_scenario_yaml(const std::string& text, const std::string& source) {
  return scenario_from([&] { return with_base(io::load_yaml_text(text, source), source, 0); },
                       source);
}

}  // namespace tofcomp::sim
