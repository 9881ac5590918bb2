#include "io/calibration_file.hpp"

#include <yaml-cpp/yaml.h>

#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/extension_yaml.hpp"
#include "io/training_choices_yaml.hpp"
#include "io/yaml_fields.hpp"

namespace tofcomp::io {
namespace {

// Doubles are written with 17 significant digits so that a file read back reproduces the
// trained model exactly.
YAML::Emitter& precise(YAML::Emitter& out) {
  out.SetDoublePrecision(std::numeric_limits<double>::max_digits10);
  return out;
}

const char* kind_name(core::BasisKind kind) {
  return kind == core::BasisKind::Polynomial ? "polynomial" : "fourier";
}

void emit_basis(YAML::Emitter& out, const core::Basis& basis) {
  out << YAML::Key << "basis" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "scaling" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "center_c" << YAML::Value << basis.scaling().center_c;
  out << YAML::Key << "half_range_c" << YAML::Value << basis.scaling().half_range_c;
  out << YAML::EndMap;
  out << YAML::Key << "terms" << YAML::Value << YAML::BeginSeq;
  for (const auto& term : basis.terms()) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "kind" << YAML::Value << kind_name(term.kind);
    out << YAML::Key << "order" << YAML::Value << term.order;
    if (term.kind == core::BasisKind::Polynomial) {
      out << YAML::Key << "form" << YAML::Value
          << (term.form == core::PolynomialForm::Legendre ? "legendre" : "raw");
    } else {
      out << YAML::Key << "f0_per_c" << YAML::Value << term.f0_per_c;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
}

core::Basis read_basis(const YamlMap& parent) {
  const YamlMap b(parent.node("basis"), parent.child_path("basis"), {"scaling", "terms"});
  const YamlMap s(b.node("scaling"), b.child_path("scaling"), {"center_c", "half_range_c"});
  const core::TemperatureScaling scaling{s.number("center_c"), s.number("half_range_c")};
  const YAML::Node list = b.node("terms");
  if (!list.IsSequence() || list.size() == 0) b.fail("terms", "must be a non-empty list");
  std::vector<core::BasisTerm> terms;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YamlMap t(list[i], b.child_path("terms") + "[" + std::to_string(i) + "]",
                    {"kind", "order", "form", "f0_per_c"});
    core::BasisTerm term;
    const std::string kind = t.text("kind");
    term.order = static_cast<int>(t.integer("order"));
    if (kind == "polynomial") {
      term.kind = core::BasisKind::Polynomial;
      const std::string form = t.text_or("form", "legendre");
      if (form != "legendre" && form != "raw") t.fail("form", "must be legendre or raw");
      term.form = form == "raw" ? core::PolynomialForm::RawPower : core::PolynomialForm::Legendre;
    } else if (kind == "fourier") {
      term.kind = core::BasisKind::Fourier;
      term.f0_per_c = t.number("f0_per_c");
    } else {
      t.fail("kind", "must be polynomial or fourier, not '" + kind + "'");
    }
    terms.push_back(term);
  }
  try {
    return core::Basis(terms, scaling);
  } catch (const core::InvalidInput& e) {
    b.fail("terms", std::string("do not make a valid basis: ") + e.what());
  }
}

}  // namespace

std::string calibration_to_yaml(const core::Calibration& c) {
  c.model.validate();
  YAML::Emitter out;
  precise(out);
  out << YAML::BeginMap;
  out << YAML::Key << "schema" << YAML::Value << kCalibrationSchema;
  out << YAML::Key << "version" << YAML::Value << kCalibrationVersion;

  out << YAML::Key << "provenance" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "data_set" << YAML::Value << c.provenance.data_set;
  out << YAML::Key << "created_utc" << YAML::Value << c.provenance.created_utc;
  out << YAML::Key << "software_version" << YAML::Value << c.provenance.software_version;
  out << YAML::Key << "samples" << YAML::Value << c.provenance.samples;
  out << YAML::Key << "notes" << YAML::Value << c.provenance.notes;
  out << YAML::EndMap;

  out << YAML::Key << "thermal" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "r1_k_per_w" << YAML::Value << c.thermal.r1_k_per_w;
  out << YAML::Key << "r2_k_per_w" << YAML::Value << c.thermal.r2_k_per_w;
  out << YAML::Key << "c1_j_per_k" << YAML::Value << c.thermal.c1_j_per_k;
  out << YAML::Key << "c2_j_per_k" << YAML::Value << c.thermal.c2_j_per_k;
  out << YAML::Key << "power_w" << YAML::Value << c.thermal.power_w;
  out << YAML::Key << "ambient_c" << YAML::Value << c.ambient_c;
  out << YAML::Key << "process_noise_case_k2_per_s" << YAML::Value
      << c.kalman_noise.case_process_psd_k2_per_s;
  out << YAML::Key << "process_noise_junction_k2_per_s" << YAML::Value
      << c.kalman_noise.junction_process_psd_k2_per_s;
  out << YAML::Key << "sensor_noise_k2" << YAML::Value << c.kalman_noise.measurement_variance_k2;
  out << YAML::EndMap;

  out << YAML::Key << "measurement" << YAML::Value << YAML::BeginMap;
  emit_basis(out, c.model.basis);
  out << YAML::Key << "theta_mm" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (Eigen::Index i = 0; i < c.model.theta.size(); ++i) out << c.model.theta[i];
  out << YAML::EndSeq;
  out << YAML::Key << "modes" << YAML::Value << YAML::BeginSeq;
  for (int i = 0; i < c.model.mixture.modes(); ++i) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "offset_mm" << YAML::Value << c.model.mixture.mean[i];
    out << YAML::Key << "variance_mm2" << YAML::Value << c.model.mixture.variance[i];
    out << YAML::Key << "weight" << YAML::Value << c.model.mixture.weight[i];
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (c.model.trained_junction_c) {
    out << YAML::Key << "trained_junction_c" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "min" << YAML::Value << c.model.trained_junction_c->min_c;
    out << YAML::Key << "max" << YAML::Value << c.model.trained_junction_c->max_c;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  if (c.extension) emit_extension(out, *c.extension, c.model.mixture);
  emit_training_choices(out, c.choices);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void write_calibration_file(const std::string& file, const core::Calibration& calibration) {
  write_file_atomically(file, calibration_to_yaml(calibration));
}

namespace {

// The calibration in a document read from `file` (a file name, or what names the text).
core::Calibration calibration_from_document(const std::function<YAML::Node()>& load,
                                            const std::string& file) {
  try {
    const YAML::Node root = load();
    const YamlMap top(
        root, "",
        {"schema", "version", "provenance", "thermal", "measurement", "extension", "choices"});
    if (top.text("schema") != kCalibrationSchema) {
      top.fail("schema",
               std::string("must be ") + kCalibrationSchema + ", not '" + top.text("schema") + "'");
    }
    const long version = top.integer("version");
    if (version < kOldestCalibrationVersion || version > kCalibrationVersion) {
      top.fail("version", "is " + std::to_string(version) + "; this tofcomp reads versions " +
                              std::to_string(kOldestCalibrationVersion) + " to " +
                              std::to_string(kCalibrationVersion));
    }
    core::Calibration c;
    const YamlMap p(top.node("provenance"), "provenance",
                    {"data_set", "created_utc", "software_version", "samples", "notes"});
    c.provenance.data_set = p.text("data_set");
    c.provenance.created_utc = p.text("created_utc");
    c.provenance.software_version = p.text("software_version");
    c.provenance.samples = p.integer("samples");
    c.provenance.notes = p.text_or("notes", "");

    const YamlMap t(
        top.node("thermal"), "thermal",
        {"r1_k_per_w", "r2_k_per_w", "c1_j_per_k", "c2_j_per_k", "power_w", "ambient_c",
         "process_noise_case_k2_per_s", "process_noise_junction_k2_per_s", "sensor_noise_k2"});
    c.thermal.r1_k_per_w = t.number("r1_k_per_w");
    c.thermal.r2_k_per_w = t.number("r2_k_per_w");
    c.thermal.c1_j_per_k = t.number("c1_j_per_k");
    c.thermal.c2_j_per_k = t.number("c2_j_per_k");
    c.thermal.power_w = t.number("power_w");
    c.ambient_c = t.number("ambient_c");
    c.kalman_noise.case_process_psd_k2_per_s = t.number("process_noise_case_k2_per_s");
    c.kalman_noise.junction_process_psd_k2_per_s = t.number("process_noise_junction_k2_per_s");
    c.kalman_noise.measurement_variance_k2 = t.number("sensor_noise_k2");
    try {
      c.thermal.validate();
      c.kalman_noise.validate();
    } catch (const core::InvalidInput& e) {
      throw YamlSchemaError(std::string("thermal: ") + e.what());
    }

    const YamlMap m(top.node("measurement"), "measurement",
                    {"basis", "theta_mm", "modes", "trained_junction_c"});
    if (m.has("trained_junction_c")) {
      const YamlMap range(m.node("trained_junction_c"), "measurement.trained_junction_c",
                          {"min", "max"});
      c.model.trained_junction_c = core::TemperatureRange{range.number("min"), range.number("max")};
    }
    c.model.basis = read_basis(m);
    c.model.theta = read_vector(m, "theta_mm");
    const YAML::Node modes = m.node("modes");
    if (!modes.IsSequence() || modes.size() == 0) m.fail("modes", "must be a non-empty list");
    const auto count = static_cast<Eigen::Index>(modes.size());
    c.model.mixture.mean.resize(count);
    c.model.mixture.variance.resize(count);
    c.model.mixture.weight.resize(count);
    for (std::size_t i = 0; i < modes.size(); ++i) {
      const YamlMap mode(modes[i], "measurement.modes[" + std::to_string(i) + "]",
                         {"offset_mm", "variance_mm2", "weight"});
      const auto j = static_cast<Eigen::Index>(i);
      c.model.mixture.mean[j] = mode.number("offset_mm");
      c.model.mixture.variance[j] = mode.number("variance_mm2");
      c.model.mixture.weight[j] = mode.number("weight");
    }
    try {
      c.model.validate();
    } catch (const core::InvalidInput& e) {
      throw YamlSchemaError(std::string("measurement: ") + e.what());
    }
    if (top.has("extension")) c.extension = read_extension(top, c.model.mixture, version);
    c.choices = read_training_choices(top);
    return c;
  } catch (const YamlSchemaError& e) {
    const std::string what = e.what();
    if (what.rfind(file, 0) == 0) throw;
    throw YamlSchemaError(file + ": " + what);
  }
}

}  // namespace

core::Calibration read_calibration_file(const std::string& file) {
  return calibration_from_document([&] { return load_yaml_file(file); }, file);
}

core::Calibration parse_calibration_yaml(const std::string& text, const std::string& source) {
  return calibration_from_document([&] { return load_yaml_text(text, source); }, source);
}

}  // namespace tofcomp::io
