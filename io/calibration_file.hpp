// The calibration file: the contract between training (`tofcomp train`) and everything that
// compensates (`tofcomp test`, the daemon). YAML with a versioned schema; every parameter
// carries its unit in its key. Reference: docs/calibration-file.md.
#pragma once

#include <optional>
#include <string>

#include "core/kalman.hpp"
#include "core/measurement_model.hpp"
#include "core/model_extension.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::io {

inline constexpr const char* kCalibrationSchema = "tofcomp-calibration";
inline constexpr int kCalibrationVersion = 1;

struct Provenance {
  std::string data_set;          // the measured data trained on
  std::string created_utc;       // ISO 8601
  std::string software_version;  // tofcomp's version
  long samples = 0;              // ranges used for training
  std::string notes;
};

struct Calibration {
  core::ThermalParameters thermal{};
  core::ThermalNoise noise;  // of the junction-temperature Kalman filter (§3.3)
  double ambient_c = 22.0;   // used when the data carry no ambient column
  core::MeasurementModel model;
  // What the residual diagnosis added to Eq. 8 (`tofcomp diagnose`); its noise replaces
  // model.noise wherever ranges are compensated. Absent: the paper's model.
  std::optional<core::ModelExtension> extension;
  Provenance provenance;
};

// The token of an effect in the file's extension.effect (and the daemon's status): its name
// with '_' for spaces and hyphens, e.g. outliers, time_drift, mode_persistence.
std::string effect_token(core::EffectKind kind);

// Writes atomically (temporary file, fsync, rename, fsync of the directory): a crash at any
// moment leaves the old file or the new one.
void write_calibration_file(const std::string& file, const Calibration& calibration);
std::string calibration_to_yaml(const Calibration& calibration);

// Throws YamlSchemaError naming the file and key: another schema or version, a missing or
// unknown key, a value out of range (θ not matching the basis, weights not summing to one).
Calibration read_calibration_file(const std::string& file);

}  // namespace tofcomp::io
