// The paper's figures of `tofcomp evaluate --figures DIR` and `tofcomp test --figures DIR`: the
// data behind them (cli/figure_data.hpp) in DIR/data/, with a context.json of what was trained
// and tested, drawn into DIR/figures/*.png by the report's renderer (cli/report_renderer.hpp),
// the same drawings `tofcomp diagnose --report` makes of them. Figures that need a diagnosis
// (the GLR curves, EM testing's trace and cost, the error moments) are left out.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "calibration/compensation.hpp"
#include "calibration/measured_data.hpp"
#include "calibration/training.hpp"
#include "calibration/window_evaluation.hpp"
#include "cli/report_renderer.hpp"

namespace tofcomp::cli {

// What a figure directory is drawn from: the tested part and its compensation, the windows,
// and, when the command trained, the thermal fit and EM's training trace.
struct FigureInputs {
  const calibration::MeasuredData& test;
  const core::Calibration& calibration;
  const calibration::Compensation& compensation;
  const std::vector<calibration::WindowEvaluation>& windows;
  long stride = 1;
  const calibration::ThermalFit* thermal = nullptr;
  const core::EmTrainResult* training = nullptr;
};

// Writes DIR/data/ (the CSVs, and context.json: `context`, the command's own facts, with the
// calibration, the window lengths and the stride added) and draws DIR/figures/. Throws
// core::Error when the renderer fails.
void write_and_draw_figures(const std::filesystem::path& directory, const FigureInputs& inputs,
                            nlohmann::json context, const ReportRenderer& renderer,
                            bool show_progress);

}  // namespace tofcomp::cli
