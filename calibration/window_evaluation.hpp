// §8.4 on measured data: the three window estimators (raw mean, mean of y − Hθ̂ centred by the
// modes' common offset Σπ_iμ_i, EM d̂ of §6)
// over windows of each length, and their error moments where the true distance is known.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "calibration/compensation.hpp"
#include "calibration/measured_data.hpp"
#include "core/calibration.hpp"
#include "core/estimators.hpp"

namespace tofcomp::calibration {

struct WindowEvaluation {
  Eigen::Index window = 0;
  // The Cramér–Rao bound of d for this window length as a mean absolute error
  // (core/cramer_rao.hpp), from the calibration's modes with their bias known.
  double cramer_rao_mae_mm = 0.0;
  core::WindowEstimates estimates;
  bool has_truth = false;
  Eigen::VectorXd truth_mm;           // mean true distance of each window
  core::ErrorMoments em;              // d̂
  core::ErrorMoments raw;             // ȳ
  core::ErrorMoments bias_corrected;  // mean of y − Hθ̂ − Σπ_iμ_i
  // d̂ apart on the windows whose every range lies inside the junction temperatures the
  // calibration was trained on, and on those with a range beyond them (where the bias is
  // extrapolated along its tangent, core/measurement_model.hpp). Without a stored trained range
  // every window counts as inside.
  core::ErrorMoments em_inside_trained;
  core::ErrorMoments em_beyond_trained;
  std::vector<bool> beyond_trained;  // per window, where the truth is known
  // Windows left out for holding a range that was not to be counted (not still).
  Eigen::Index windows_left_out = 0;
};

// The three estimators on every window of each length (d̂ under the calibration's mixture, extended
// or not) (stride apart), and their error moments
// where the data carry the true distance (Fig. 16-19). `progress` gets the fraction done.
// `counted` (empty: every range counts): per range, whether a window may hold it; a window
// holding another is left out (WindowEvaluation::windows_left_out). `band` (null: the
// calibration's own model): the model whose trained junction range inside and beyond are judged
// against (a field calibration tested inside and beyond its bench calibration's band).
std::vector<WindowEvaluation> evaluate_windows(const MeasuredData& data,
                                               const core::Calibration& calibration,
                                               const Compensation& compensation,
                                               const std::vector<Eigen::Index>& windows,
                                               Eigen::Index stride,
                                               const std::function<void(double)>& progress = {},
                                               const std::vector<bool>& counted = {},
                                               const core::MeasurementModel* band = nullptr);

// The windows of several beams' evaluations (each with the same window lengths, in the same
// order) as one: their estimates and truths side by side and the error moments over them all.
std::vector<WindowEvaluation> pool_window_evaluations(
    const std::vector<std::vector<WindowEvaluation>>& per_beam);

}  // namespace tofcomp::calibration
