// A calibration: what training (§3 and §5) learns of one scanner, and all that compensation
// (Eq. 8 offline, §6 in the daemon) needs: the thermal network with its Kalman noise (§3.3), the
// measurement model of Eq. 8 (basis, θ, the lasing modes' mixture), an optional extension of
// Eq. 8 found by the residual diagnosis, and where it came from. A plain value: its file format
// is io/calibration_file.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/extended_mixture.hpp"
#include "core/kalman.hpp"
#include "core/measurement_model.hpp"
#include "core/model_extension.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::core {

struct Provenance {
  std::string data_set;          // the measured data trained on
  std::string created_utc;       // ISO 8601
  std::string software_version;  // tofcomp's version
  long samples = 0;              // ranges used for training
  std::string notes;
};

// What training chose from the data where the paper leaves the choice to the designer, and the
// evidence for it (calibration/training.hpp): kept with the calibration, so that a file says why
// it has the structure it has. Each part is absent when the user gave that choice.
struct CandidateRecord {
  std::string name;  // e.g. "polynomial(6, legendre), 3 modes"
  int parameters = 0;
  double held_out_log_likelihood = 0.0;  // per held-out range
  double glr = 0.0;                      // Algorithm 2
  double bic = 0.0;
};
struct StructureRecord {
  std::string method;  // how the choice was made
  std::string chosen;  // the chosen candidate's name
  std::string best_by_glr;
  std::string best_by_bic;
  std::vector<CandidateRecord> candidates;  // those that could be trained
};
struct KalmanNoiseRecord {
  std::string method;
  std::vector<std::string> held;  // the levels the data did not determine, kept at their prior
};
// The junction's dynamics from the ranges (calibration/junction_dynamics.hpp).
struct JunctionDynamicsRecord {
  std::string method;
  bool from_ranges = false;  // the ranges rejected the case-log fit's junction
  double rise_k = 0.0;       // P·R1 of the calibration's thermal network
  double time_constant_s = 0.0;  // R1·C1
  double case_log_rise_k = 0.0;  // the case-log fit's
  double case_log_time_constant_s = 0.0;
  double block_p = 1.0;  // the t-test's p-value over blocks of ranges
  // The ranges rejected the case log's junction process noise q_j: the calibration's
  // kalman_noise holds it at the level the case log's fit started from.
  bool junction_noise_held = false;
};
struct TrainingChoices {
  std::optional<KalmanNoiseRecord> kalman_noise;
  std::optional<StructureRecord> structure;
  std::optional<JunctionDynamicsRecord> junction_dynamics;
};

struct Calibration {
  ThermalParameters thermal{};
  ThermalNoise kalman_noise;  // the noise levels of the junction-temperature Kalman filter (§3.3)
  double ambient_c = 22.0;    // used when the data carry no ambient column
  MeasurementModel model;
  // What the residual diagnosis added to Eq. 8 (`tofcomp diagnose`); its extended mixture replaces
  // model.mixture wherever ranges are compensated. Absent: the paper's model.
  std::optional<ModelExtension> extension;
  Provenance provenance;
  TrainingChoices choices;
};

// The mixture of Eq. 8 that ranges are compensated under: the extension's when the calibration
// has one, else the paper's mixture (without extensions). The one definition for the offline
// pipeline (calibration/) and the daemon's path (realtime/).
ExtendedMixture compensation_mixture(const Calibration& calibration);

}  // namespace tofcomp::core
