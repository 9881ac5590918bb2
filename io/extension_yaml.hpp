// The calibration file's `extension:` section (docs/calibration-file.md): the terms of the
// grammar (core/effect_grammar.hpp) the model search kept, as core::ModelExtension holds them.
// Version 2 of the file writes the grammar's terms; a version 1 file's extension (one effect:
// effect, covariate, covariate_mm, time_constant_s, bins on the junction temperature) is read
// into the same terms, so that a calibration written before still loads.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string_view>

#include "core/model_extension.hpp"
#include "io/yaml_fields.hpp"

namespace tofcomp::io {

// Throws core::InvalidInput when the extension is invalid or its modes are not `modes` (the
// measurement's, which the file stores once).
void emit_extension(YAML::Emitter& out, const core::ModelExtension& extension,
                    const core::MixtureParameters& modes);
// Throws YamlSchemaError naming the key at fault.
core::ModelExtension read_extension(const YamlMap& top, const core::MixtureParameters& modes,
                                    long version);

// A list of finite numbers, and a list of equally long lists of them.
Eigen::VectorXd read_vector(const YamlMap& parent, std::string_view key);
Eigen::MatrixXd read_matrix(const YamlMap& parent, std::string_view key);  // empty when absent
void emit_vector(YAML::Emitter& out, const char* key, const Eigen::VectorXd& v);
void emit_matrix(YAML::Emitter& out, const char* key, const Eigen::MatrixXd& m);  // none when empty

}  // namespace tofcomp::io
