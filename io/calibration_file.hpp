// The calibration file (core/calibration.hpp written as YAML): the contract between training
// (`tofcomp train`) and everything that compensates (`tofcomp test`, the daemon). YAML with a
// versioned schema; every parameter carries its unit in its key. Reference:
// docs/calibration-file.md.
#pragma once

#include <optional>
#include <string>

#include "core/calibration.hpp"

namespace tofcomp::io {

inline constexpr const char* kCalibrationSchema = "tofcomp-calibration";
// Version 2 writes the extension as the grammar's terms (io/extension_yaml.hpp); version 1 files,
// whose extension held one effect, still load.
inline constexpr int kCalibrationVersion = 2;
inline constexpr int kOldestCalibrationVersion = 1;

// Writes atomically (temporary file, fsync, rename, fsync of the directory): a crash at any
// moment leaves the old file or the new one.
void write_calibration_file(const std::string& file, const core::Calibration& calibration);
std::string calibration_to_yaml(const core::Calibration& calibration);

// Throws YamlSchemaError naming the file and key: another schema or version, a missing or
// unknown key, a value out of range (θ not matching the basis, weights not summing to one).
core::Calibration read_calibration_file(const std::string& file);
// The same for the text of a calibration file; `source` names it in errors.
core::Calibration parse_calibration_yaml(const std::string& text, const std::string& source);

}  // namespace tofcomp::io
