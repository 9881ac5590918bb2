// A calibration scored on every beam of a record that carries a reference distance (§8.4's
// window estimators, issue 56's `tofcomp test`): each beam's ranges split into still surfaces
// (calibration/still_surfaces.hpp) so that a window holding a range that is not still (a person
// or a forklift in the beam, a gross error) is left out and counted instead of scored as if the
// reference held there; inside and beyond the calibration's junction band apart, per beam and
// pooled over the beams.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibration/compensation.hpp"
#include "calibration/measured_data.hpp"
#include "calibration/window_evaluation.hpp"
#include "core/calibration.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::calibration {

struct BeamScore {
  MeasuredData data;
  Compensation compensation;
  long set_apart = 0;  // ranges not still
  std::vector<WindowEvaluation> windows;
};

struct BeamScores {
  std::vector<BeamScore> beams;                 // those with a reference on every range
  std::vector<int> beams_without_reference;     // left out
  std::vector<WindowEvaluation> pooled;         // the windows of every scored beam
  double still_gate_mm = 0.0;
};

// The beams of `table` that hold ranges, in order.
std::vector<int> beams_with_ranges(const io::MeasurementTable& table);

// Scores `calibration` on every beam of `table` (only `beam` when given) whose every range has a
// reference. Throws core::InvalidInput when no beam has one (naming the source), or when `beam`
// holds no range.
// `band` (null: the calibration's own): the model whose trained junction range inside and
// beyond are judged against.
BeamScores score_beams(const io::MeasurementTable& table, const std::string& source,
                       const core::Calibration& calibration, std::optional<int> beam,
                       const std::vector<Eigen::Index>& windows, Eigen::Index stride,
                       const std::function<void(double)>& progress = {},
                       const core::MeasurementModel* band = nullptr);

}  // namespace tofcomp::calibration
