// Training in the field (issue 56): Eq. 8's bias H(t)θ and lasing modes learned from records
// whose distances nobody measured. Each beam's ranges are split into still episodes (core/
// still_episodes.hpp); each episode's distance is a nuisance parameter of the EM (core/
// field_em.hpp), so a wall seen over the temperatures a day brings teaches the bias there, where
// no bench reached. A bench calibration gives what ranges of unknown distance cannot: the thermal
// network and Kalman noise that put a junction temperature on every range (§3), a candidate basis
// (the basis is chosen again over the temperatures the records span) and the number of modes, and the constant the distances and the bias share. Ranges of a record
// with a reference (true_range_mm) enter the same fit with their distance known and pin that
// constant themselves; without any, the bias is matched to the bench calibration's over the
// bench's junction band.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "calibration/field_structure.hpp"
#include "calibration/thermal_fit.hpp"
#include "core/calibration.hpp"
#include "core/field_em.hpp"
#include "core/still_episodes.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::calibration {

// A record of one or many beams, as read, and its name for messages and provenance.
struct FieldRecord {
  io::MeasurementTable table;
  std::string source;
};

// Points of the bench's junction band over which the field bias is matched to the bench's.
inline constexpr int kBandMatchPoints = 101;

struct FieldTrainSettings {
  ThermalFitSettings thermal;  // without a bench calibration: the case log's fit
  // gate_mm 0: from the bench calibration's modes (calibration/still_surfaces.hpp).
  core::StillEpisodeOptions still;
  int max_iterations = 5000;
};

// What the still detector made of one beam of one record.
struct BeamStillness {
  std::string source;
  int beam = 0;
  long ranges = 0;
  long with_reference = 0;  // ranges of known distance (not segmented)
  long still = 0;           // ranges in still episodes
  long episodes = 0;
  long set_apart = 0;
};

struct FieldTraining {
  core::Calibration calibration;
  core::FieldEmResult em;
  std::vector<BeamStillness> beams;
  long ranges_used = 0;
  long ranges_with_reference = 0;
  int episodes = 0;
  double gate_mm = 0.0;
  // The basis chosen on held-out time blocks (calibration/field_structure.hpp).
  FieldBasisChoice basis;
  // How the constant d and the bias share was fixed, in words.
  std::string constant;
  bool bench_given = false;
};

using FieldProgress = std::function<void(double share, const std::string& stage)>;

// Trains on every beam of every record, from `bench` when given; without it the thermal network
// is fitted to the records' case log, the modes start from the data, and unless some range has a
// reference the constant is not determined (the modes' mean offset set to 0). Throws
// core::InvalidInput when the records hold no still episode and no range of known distance,
// core::Error when a stage fails.
FieldTraining train_in_field(const std::vector<FieldRecord>& records,
                             const core::Calibration* bench, const FieldTrainSettings& settings,
                             const FieldProgress& progress = {});

}  // namespace tofcomp::calibration
