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
#include "calibration/model_search.hpp"
#include "calibration/training.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

struct ReportOptions {
  std::string directory;  // empty: no report
  // When a report was asked for, makes its directory and finds its renderer, so that what the
  // report lacks fails before the diagnosis's long work; otherwise nothing.
  void check_if_requested() const;
  // Writes the report of `diagnosis` (diagnose's JSON) into `directory` when one was asked for;
  // otherwise nothing. `trained`: the paper's model the search started from and the residual
  // tests ran under; `search`: the search, its calibration the final one with the kept terms.
  // `windows`: the lengths of Fig. 16-17 and of the error table (diagnose's --windows).
  void write_if_requested(const calibration::MeasuredData& measured,
                          const calibration::TrainSettings& settings,
                          const nlohmann::json& diagnosis, const core::Calibration& trained,
                          const calibration::ModelSearchResult& search,
                          const core::Diagnosis& residual_diagnosis,
                          const std::vector<Eigen::Index>& windows, bool show_progress) const;
};

// Adds --report DIR to cmd.
std::shared_ptr<ReportOptions> add_report_options(CLI::App& cmd);

}  // namespace tofcomp::cli
