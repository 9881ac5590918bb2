// The options of `tofcomp diagnose` that ask for the HTML report (cli/diagnosis_report.hpp),
// registered in one place so that the command itself needs one line to take them and one call
// to honour them.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "calibration/training.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

struct ReportOptions {
  std::string directory;  // empty: no report
  // Writes the report of `diagnosis` into `directory` when one was asked for; otherwise nothing.
  // `windows`: the lengths of Fig. 16-17 and of the error table (diagnose's --windows).
  void write_if_requested(const calibration::MeasuredData& measured,
                          const calibration::TrainSettings& settings,
                          const nlohmann::json& diagnosis, const core::Calibration& diagnosed,
                          const core::Diagnosis& residual_diagnosis,
                          const std::vector<Eigen::Index>& windows, bool show_progress) const;
};

// Adds --report DIR to cmd.
std::shared_ptr<ReportOptions> add_report_options(CLI::App& cmd);

}  // namespace tofcomp::cli
