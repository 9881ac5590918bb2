#include "cli/report_options.hpp"

#include "cli/diagnosis_report.hpp"

namespace tofcomp::cli {

void ReportOptions::check_if_requested() const {
  if (!directory.empty()) check_report_possible(directory);
}

void ReportOptions::write_if_requested(
    const calibration::MeasuredData& measured, const calibration::TrainSettings& settings,
    const nlohmann::json& diagnosis, const core::Calibration& trained,
    const calibration::ModelSearchResult& search, const core::Diagnosis& residual_diagnosis,
    const std::vector<Eigen::Index>& windows, bool show_progress) const {
  if (directory.empty()) return;
  ReportSettings report;
  report.windows = windows;
  write_diagnosis_report(directory, measured, settings,
                         {diagnosis, trained, search, residual_diagnosis}, report, show_progress);
}

std::shared_ptr<ReportOptions> add_report_options(CLI::App& cmd) {
  auto options = std::make_shared<ReportOptions>();
  cmd.add_option("--report", options->directory,
                 "Also write an HTML report into this directory: the search's verdict and "
                 "errors first, the figure of each term it kept as fitted, the paper's figures "
                 "on these data (held-out half), the residual tests as evidence "
                 "(DIR/index.html; needs python3-matplotlib)")
      ->type_name("DIR");
  return options;
}

}  // namespace tofcomp::cli
