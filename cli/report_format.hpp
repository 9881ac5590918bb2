// The text and JSON forms of results that several subcommands print.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/pipeline.hpp"
#include "core/estimators.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::cli {

nlohmann::json to_json(const core::ErrorMoments& m);
nlohmann::json to_json(const ThermalFit& fit);
nlohmann::json to_json(const io::Calibration& c);
nlohmann::json to_json(const std::vector<WindowEvaluation>& evaluations);

std::string thermal_fit_text(const ThermalFit& fit);
std::string calibration_text(const io::Calibration& c);
// The table of Fig. 18-19: per window length, the three estimators' mean error, mean absolute
// error, variance of the absolute error and RMSE, and the MAE ratio raw / compensated.
std::string window_table_text(const std::vector<WindowEvaluation>& evaluations);

}  // namespace tofcomp::cli
