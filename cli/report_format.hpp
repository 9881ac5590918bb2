// The text and JSON forms of results that several subcommands print.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "calibration/training.hpp"
#include "calibration/window_evaluation.hpp"
#include "core/estimators.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::cli {

nlohmann::json to_json(const core::ErrorMoments& m);
nlohmann::json to_json(const calibration::ThermalFit& fit);
nlohmann::json to_json(const core::Calibration& c);
nlohmann::json to_json(const std::vector<calibration::WindowEvaluation>& evaluations);
// What `tofcomp train --json` prints of a training: {calibration, thermal_fit, choices,
// em_iterations, em_converged, log_likelihood}.
nlohmann::json training_json(const calibration::Training& t);

std::string thermal_fit_text(const calibration::ThermalFit& fit);
std::string calibration_text(const core::Calibration& c);
// The table of Fig. 18-19: per window length, the three estimators' mean error, mean absolute
// error, variance of the absolute error and RMSE, and the MAE ratio raw / compensated. The
// middle estimator is the mean of y − Hθ̂ centred by the modes' common offset Σ π_i μ_i
// (core/estimators.hpp); the JSON keeps its key, bias_corrected_mean.
std::string window_table_text(const std::vector<calibration::WindowEvaluation>& evaluations);

}  // namespace tofcomp::cli
