// tofcomp test DATA --calibration C.yaml: estimate d on windows with a trained calibration
// (§6, §8.4) and, where the data carry the true distance, the three estimators' errors.
#include "cli/command.hpp"
#include "cli/number_checks.hpp"

#include "cli/figure_data.hpp"
#include "cli/progress.hpp"
#include "cli/report_format.hpp"
#include "cli/shared_options.hpp"

namespace tofcomp::cli {

void register_test(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "test",
      "Estimate the distance on windows of ranges with a calibration (EM testing) and "
      "report the errors of d̂, ȳ and mean(y − Hθ̂) − Σπμ where the truth is known");
  auto data = add_data_options(*cmd);
  auto calibration = std::make_shared<std::string>();
  auto windows = std::make_shared<std::string>("200,400,800");
  auto stride = std::make_shared<long>(1);
  auto figures = std::make_shared<std::string>();
  cmd->add_option("--calibration", *calibration, "Calibration file (from tofcomp train)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--windows", *windows, "Window lengths, comma separated")->capture_default_str();
  cmd->add_option("--stride", *stride, "Samples between window starts (1: every window)")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--figures", *figures, "Directory for the data behind the paper's figures, as CSV files (drawn by "
                  "tofcomp diagnose --report)");
  cmd->callback([&common, &run, data, calibration, windows, stride, figures] {
    run = [&common, data, calibration, windows, stride, figures] {
      Progress progress("test", !common.quiet);
      const core::Calibration c = io::read_calibration_file(*calibration);
      const calibration::MeasuredData measured = data->load();
      const calibration::Compensation compensation = calibration::compensate(measured, c);
      const auto evaluations =
          calibration::evaluate_windows(measured, c, compensation, parse_windows(*windows), *stride,
                                        [&](double f) { progress.update(f, "windows"); });
      if (!figures->empty()) {
        write_figure_data(*figures, measured, c, compensation, evaluations, nullptr, nullptr);
      }
      progress.done();
      CommandResult result;
      result.json = {{"windows", to_json(evaluations)}, {"samples", measured.range_mm.size()}};
      result.text = window_table_text(evaluations);
      return result;
    };
  });
}

}  // namespace tofcomp::cli
