// The inputs of Algorithm 1 (§3.2) as a YAML file: the laser's and the case's datasheet values
// and one equilibrium measurement. Reference: config/lms200-datasheet.yaml.
#pragma once

#include <string>

#include "core/thermal_identification.hpp"

namespace tofcomp::io {

// Throws YamlSchemaError naming the file and key on a missing, unknown or non-numeric key.
core::DatasheetThermalData read_datasheet_file(const std::string& file);
// The same for the file's text in memory; `source` names it in errors.
core::DatasheetThermalData parse_datasheet(const std::string& text, const std::string& source);

}  // namespace tofcomp::io
