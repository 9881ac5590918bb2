// The calibration file's `choices` section: what training chose from the data and its evidence
// (core::TrainingChoices), written and read strictly. docs/calibration-file.md shows the layout.
#pragma once

#include <yaml-cpp/yaml.h>

#include "core/calibration.hpp"
#include "io/yaml_fields.hpp"

namespace tofcomp::io {

// Writes `choices:` when either part is present; nothing otherwise.
void emit_training_choices(YAML::Emitter& out, const core::TrainingChoices& choices);
// Reads the `choices` key of the file's top map (absent: nothing was chosen). Throws
// YamlSchemaError naming the key at fault.
core::TrainingChoices read_training_choices(const YamlMap& top);

}  // namespace tofcomp::io
