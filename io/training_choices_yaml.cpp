#include "io/training_choices_yaml.hpp"

namespace tofcomp::io {

void emit_training_choices(YAML::Emitter& out, const core::TrainingChoices& choices) {
  if (!choices.kalman_noise && !choices.structure && !choices.junction_dynamics) return;
  out << YAML::Key << "choices" << YAML::Value << YAML::BeginMap;
  if (choices.kalman_noise) {
    out << YAML::Key << "kalman_noise" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "method" << YAML::Value << choices.kalman_noise->method;
    out << YAML::Key << "held" << YAML::Value << YAML::Flow << choices.kalman_noise->held;
    out << YAML::EndMap;
  }
  if (choices.structure) {
    const core::StructureRecord& s = *choices.structure;
    out << YAML::Key << "structure" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "method" << YAML::Value << s.method;
    out << YAML::Key << "chosen" << YAML::Value << s.chosen;
    out << YAML::Key << "best_by_glr" << YAML::Value << s.best_by_glr;
    out << YAML::Key << "best_by_bic" << YAML::Value << s.best_by_bic;
    out << YAML::Key << "candidates" << YAML::Value << YAML::BeginSeq;
    for (const core::CandidateRecord& c : s.candidates) {
      out << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "name" << YAML::Value << c.name;
      out << YAML::Key << "parameters" << YAML::Value << c.parameters;
      out << YAML::Key << "held_out_log_likelihood" << YAML::Value << c.held_out_log_likelihood;
      out << YAML::Key << "glr" << YAML::Value << c.glr;
      out << YAML::Key << "bic" << YAML::Value << c.bic;
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
    out << YAML::EndMap;
  }
  if (choices.junction_dynamics) {
    const core::JunctionDynamicsRecord& j = *choices.junction_dynamics;
    out << YAML::Key << "junction_dynamics" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "method" << YAML::Value << j.method;
    out << YAML::Key << "from_ranges" << YAML::Value << j.from_ranges;
    out << YAML::Key << "rise_k" << YAML::Value << j.rise_k;
    out << YAML::Key << "time_constant_s" << YAML::Value << j.time_constant_s;
    out << YAML::Key << "case_log_rise_k" << YAML::Value << j.case_log_rise_k;
    out << YAML::Key << "case_log_time_constant_s" << YAML::Value << j.case_log_time_constant_s;
    out << YAML::Key << "block_p" << YAML::Value << j.block_p;
    out << YAML::Key << "junction_noise_held" << YAML::Value << j.junction_noise_held;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

core::TrainingChoices read_training_choices(const YamlMap& top) {
  core::TrainingChoices choices;
  if (!top.has("choices")) return choices;
  const YamlMap section(top.node("choices"), top.child_path("choices"),
                        {"kalman_noise", "structure", "junction_dynamics"});
  if (section.has("kalman_noise")) {
    const YamlMap noise(section.node("kalman_noise"), section.child_path("kalman_noise"),
                        {"method", "held"});
    core::KalmanNoiseRecord record;
    record.method = noise.text("method");
    const YAML::Node held = noise.node("held");
    if (!held.IsSequence()) noise.fail("held", "must be a list of level names");
    for (std::size_t i = 0; i < held.size(); ++i) {
      if (!held[i].IsScalar()) noise.fail("held", "must be a list of level names");
      record.held.push_back(held[i].as<std::string>());
    }
    choices.kalman_noise = record;
  }
  if (section.has("structure")) {
    const YamlMap s(section.node("structure"), section.child_path("structure"),
                    {"method", "chosen", "best_by_glr", "best_by_bic", "candidates"});
    core::StructureRecord record;
    record.method = s.text("method");
    record.chosen = s.text("chosen");
    record.best_by_glr = s.text("best_by_glr");
    record.best_by_bic = s.text("best_by_bic");
    const YAML::Node candidates = s.node("candidates");
    if (!candidates.IsSequence()) s.fail("candidates", "must be a list");
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const YamlMap c(candidates[i], s.child_path("candidates") + "[" + std::to_string(i) + "]",
                      {"name", "parameters", "held_out_log_likelihood", "glr", "bic"});
      record.candidates.push_back({c.text("name"), static_cast<int>(c.integer("parameters")),
                                   c.number("held_out_log_likelihood"), c.number("glr"),
                                   c.number("bic")});
    }
    choices.structure = record;
  }
  if (section.has("junction_dynamics")) {
    const YamlMap j(section.node("junction_dynamics"), section.child_path("junction_dynamics"),
                    {"method", "from_ranges", "rise_k", "time_constant_s", "case_log_rise_k",
                     "case_log_time_constant_s", "block_p", "junction_noise_held"});
    core::JunctionDynamicsRecord record;
    record.method = j.text("method");
    record.from_ranges = j.boolean("from_ranges");
    record.rise_k = j.number("rise_k");
    record.time_constant_s = j.number("time_constant_s");
    record.case_log_rise_k = j.number("case_log_rise_k");
    record.case_log_time_constant_s = j.number("case_log_time_constant_s");
    record.block_p = j.number("block_p");
    // Absent in calibrations written before the ranges judged q_j.
    record.junction_noise_held = j.boolean_or("junction_noise_held", false);
    choices.junction_dynamics = record;
  }
  return choices;
}

}  // namespace tofcomp::io
