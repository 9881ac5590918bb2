// The data behind the paper's figures, written as CSV files into a directory, for plotting:
//   samples.csv          per range: time, y, junction t̂^j, bias Hθ̂, posterior of each mode,
//                        the most probable mode (0-based), the range compensated for it, and the
//                        true distance when the data carry it (Fig. 3, 4, 11, 12)
//   windows_<W>.csv      per window: start, d̂, its std, ȳ, mean(y − Hθ̂) − Σπ_iμ_i (centred,
//                        core/estimators.hpp), truth (Fig. 16-17)
//   thermal_fit.csv      held-out case temperature measured and predicted (Fig. 8)
//   em_convergence.csv   per EM iteration: μ_i, σ_i², π_i, log-likelihood (Fig. 13)
#pragma once

#include <string>
#include <vector>

#include "calibration/compensation.hpp"
#include "calibration/measured_data.hpp"
#include "calibration/training.hpp"
#include "calibration/window_evaluation.hpp"

namespace tofcomp::cli {

void write_figure_data(const std::string& directory, const calibration::MeasuredData& test,
                       const core::Calibration& calibration,
                       const calibration::Compensation& compensation,
                       const std::vector<calibration::WindowEvaluation>& windows,
                       const calibration::ThermalFit* thermal, const core::EmTrainResult* training);

}  // namespace tofcomp::cli
