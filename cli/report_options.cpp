#include "cli/report_options.hpp"

#include "cli/diagnosis_report.hpp"
#include "cli/shared_options.hpp"
#include "core/error.hpp"

namespace tofcomp::cli {

void ReportOptions::write_if_requested(const MeasuredData& measured, const TrainSettings& settings,
                                       const nlohmann::json& diagnosis, bool show_progress) const {
  if (directory.empty()) return;
  ReportSettings report;
  report.windows = parse_windows(windows);
  write_diagnosis_report(directory, measured, settings, diagnosis, report, show_progress);
}

std::shared_ptr<ReportOptions> add_report_options(CLI::App& cmd) {
  auto options = std::make_shared<ReportOptions>();
  cmd.add_option("--report", options->directory,
                 "Also write an HTML report into this directory: the paper's figures on these "
                 "data (held-out half), the findings, the extension and the errors before and "
                 "after (DIR/index.html; needs python3-matplotlib)")
      ->type_name("DIR");
  cmd.add_option("--report-windows", options->windows,
                 "Window lengths of the report's Fig. 16-17 and error table, comma separated")
      ->capture_default_str()
      ->type_name("LIST")
      ->check(CLI::Validator(
          [](std::string& list) {
            try {
              parse_windows(list);
              return std::string();
            } catch (const core::InvalidInput&) {
              return "'" + list + "' is not a comma-separated list of window lengths >= 1";
            }
          },
          ""));
  return options;
}

}  // namespace tofcomp::cli
