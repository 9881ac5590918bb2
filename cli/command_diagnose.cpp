// tofcomp diagnose DATA --datasheet D.yaml [--calibration C.yaml]: finds in the residuals of a
// trained model what Eq. 8 lacks (core/residual_diagnosis.hpp), ranks the findings, fits the
// extension for the effect named first and judges it on held-out data
// (calibration/model_extension.hpp).
#include <fmt/format.h>

#include "calibration/diagnosis.hpp"
#include "calibration/model_extension.hpp"
#include "cli/command.hpp"
#include "cli/extension_format.hpp"
#include "cli/progress.hpp"
#include "cli/report_options.hpp"
#include "cli/shared_options.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::cli {
void register_diagnose(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "diagnose",
      "Find in the residuals what the paper's model (Eq. 8) lacks, fit the extension for the "
      "effect named first, and report the held-out error before and after");
  auto data = add_data_options(*cmd);
  auto training = add_training_options(*cmd);
  auto calibration = std::make_shared<std::string>();
  auto windows = std::make_shared<std::string>("200,400,800");
  auto stride = std::make_shared<long>(10);
  auto calibration_out = std::make_shared<std::string>();
  cmd->add_option("--calibration", *calibration,
                  "A calibration trained on these data (default: train one)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--windows", *windows, "Window lengths of the held-out comparison")
      ->capture_default_str();
  cmd->add_option("--stride", *stride, "Samples between held-out windows")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--calibration-output", *calibration_out,
                  "Write the calibration with the extension when it is kept (for tofcompd)");
  auto report = add_report_options(*cmd);
  cmd->callback(
      [&common, &run, data, training, calibration, windows, stride, calibration_out, report] {
        run = [&common, data, training, calibration, windows, stride, calibration_out, report] {
          Progress progress("diagnose", !common.quiet);
          const calibration::MeasuredData measured = data->load();
          measured.require_true_ranges();
          const std::vector<Eigen::Index> lengths = parse_windows(*windows);
          const core::Calibration c =
              calibration->empty()
                  ? calibration::train_calibration(measured, training->settings()).calibration
                  : io::read_calibration_file(*calibration);
          progress.update(0.3, "testing the residuals");
          const core::Diagnosis d = calibration::diagnose(measured, c);

          CommandResult result;
          result.json = to_json(d);
          result.text = diagnosis_text(d);
          if (d.findings.empty() || !d.findings.front().significant) {
            progress.done();
            report->write_if_requested(measured, training->settings(), result.json, c, d, lengths,
                                       !common.quiet);
            return result;
          }
          // Held-out data decide: train on the first half of the cycles, test on the rest.
          progress.update(0.5, fmt::format("fitting the extension for {}",
                                           core::effect_name(d.findings.front().kind)));
          const double split = calibration::split_time(measured, 0.5);
          const calibration::ExtensionReport e = calibration::evaluate_extension(
              d.findings.front().kind, measured.slice(-1e300, split), measured.slice(split, 1e300),
              training->settings(), lengths, *stride);
          progress.done();
          result.json["extension"] = to_json(e);
          result.text += extension_text(e);
          if (!calibration_out->empty() && e.kept) {
            io::write_calibration_file(*calibration_out, e.calibration);
            result.text += fmt::format("extended calibration written to {}\n", *calibration_out);
          }
          report->write_if_requested(measured, training->settings(), result.json, c, d, lengths,
                                     !common.quiet);
          return result;
        };
      });
}

}  // namespace tofcomp::cli
