// tofcomp evaluate DATA [--datasheet D.yaml]: the whole of §8 in one command. Train on the first
// part of the record (whole power cycles), test on the rest; print the thermal fit on the
// held-out cycles and the table of errors, raw against compensated, per window length.
#include <fmt/format.h>

#include "cli/command.hpp"
#include "cli/figure_drawing.hpp"
#include "cli/number_checks.hpp"
#include "cli/progress.hpp"
#include "cli/report_format.hpp"
#include "cli/shared_options.hpp"
#include "cli/structure_format.hpp"

namespace tofcomp::cli {

void register_evaluate(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "evaluate",
      "Train on the first part of the measured data, test on the rest, and print the "
      "error before and after compensation per window length (§8)");
  auto data = add_data_options(*cmd);
  auto training = add_training_options(*cmd);
  auto fraction = std::make_shared<double>(0.5);
  auto windows = std::make_shared<std::string>("200,400,800");
  auto stride = std::make_shared<long>(1);
  auto figures = std::make_shared<std::string>();
  auto calibration_out = std::make_shared<std::string>();
  cmd->add_option("--train-fraction", *fraction,
                  "Share of the record used for training; it ends at the nearest power-on")
      ->capture_default_str()
      ->check(between(0.05, 0.95));
  add_windows_option(*cmd, *windows, "Window lengths");
  cmd->add_option("--stride", *stride, "Samples between window starts (1: every window)")
      ->capture_default_str()
      ->check(at_least(1));
  add_figures_option(*cmd, *figures);
  cmd->add_option("--calibration-output", *calibration_out,
                  "Also write the calibration trained on the first part")
      ->type_name("FILE");
  cmd->callback([&common, &run, data, training, fraction, windows, stride, figures,
                 calibration_out] {
    run = [&common, data, training, fraction, windows, stride, figures, calibration_out] {
      Progress progress("evaluate", !common.quiet);
      // Found before any work: a missing matplotlib fails at once, not after the training.
      const std::optional<ReportRenderer> renderer =
          figures->empty() ? std::nullopt : std::optional(find_report_renderer());
      const calibration::MeasuredData all = data->load();
      const double split = calibration::split_time(all, *fraction);
      const calibration::MeasuredData train = all.slice(-1e300, split);
      const calibration::MeasuredData test = all.slice(split, 1e300);
      test.require_true_ranges();
      progress.update(0.05, "training");
      const calibration::TrainSettings settings = training->settings();
      const calibration::Training t = calibration::train_calibration(
          train, settings, &test, [&](double share, const std::string& stage) {
            progress.update(0.05 + 0.15 * share, stage);
          });
      if (!calibration_out->empty()) io::write_calibration_file(*calibration_out, t.calibration);
      const calibration::Compensation compensation = calibration::compensate(test, t.calibration);
      const auto evaluations = calibration::evaluate_windows(
          test, t.calibration, compensation, parse_windows(*windows), *stride,
          [&](double f) { progress.update(0.2 + 0.8 * f, "windows"); });
      if (renderer) {
        progress.update(1.0, "drawing the figures");
        write_and_draw_figures(
            *figures,
            FigureInputs{test, t.calibration, compensation, evaluations, *stride, &t.thermal,
                         &t.em},
            {{"split_time_s", split}, {"training_samples", train.range_mm.size()}}, *renderer,
            !common.quiet);
      }
      progress.done();
      CommandResult result;
      result.json = {{"split_time_s", split},
                     {"training_samples", train.range_mm.size()},
                     {"test_samples", test.range_mm.size()},
                     {"thermal_fit", to_json(t.thermal)},
                     {"choices", choices_json(t)},
                     {"calibration", to_json(t.calibration)},
                     {"windows", to_json(evaluations)}};
      result.text = fmt::format("trained on {} ranges before t = {:.0f} s, tested on {} after\n",
                                train.range_mm.size(), split, test.range_mm.size()) +
                    thermal_fit_text(t.thermal) + choices_text(t) +
                    calibration_text(t.calibration) +
                    "error of the window estimates against the true distance (§8.4):\n" +
                    window_table_text(evaluations);
      return result;
    };
  });
}

}  // namespace tofcomp::cli
