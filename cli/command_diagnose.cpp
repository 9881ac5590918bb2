// tofcomp diagnose DATA --datasheet D.yaml [--calibration C.yaml]: finds in the residuals of a
// trained model what Eq. 8 lacks (core/residual_diagnosis.hpp) and ranks the findings.
#include <fmt/format.h>

#include "cli/command.hpp"
#include "cli/covariate_extension.hpp"
#include "cli/progress.hpp"
#include "cli/report_options.hpp"
#include "cli/shared_options.hpp"

namespace tofcomp::cli {
void register_diagnose(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "diagnose",
      "Find in the residuals what the paper's model (Eq. 8) lacks: each candidate "
      "effect with its test statistic and p-value, most significant first");
  auto data = add_data_options(*cmd);
  auto training = add_training_options(*cmd);
  auto calibration = std::make_shared<std::string>();
  auto window = std::make_shared<long>(400);
  auto stride = std::make_shared<long>(10);
  cmd->add_option("--calibration", *calibration,
                  "A calibration trained on these data (default: train one)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--window", *window, "Window length of the held-out comparison")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stride", *stride, "Samples between held-out windows")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  auto report = add_report_options(*cmd);
  cmd->callback([&common, &run, data, training, calibration, window, stride, report] {
    run = [&common, data, training, calibration, window, stride, report] {
      Progress progress("diagnose", !common.quiet);
      const MeasuredData measured = data->load();
      measured.require_true_ranges();
      const io::Calibration c = calibration->empty()
                                    ? train_calibration(measured, training->settings()).calibration
                                    : io::read_calibration_file(*calibration);
      progress.update(0.5, "testing the residuals");
      const core::Diagnosis d = diagnose(measured, c);
      progress.done();

      CommandResult result;
      result.json["findings"] = nlohmann::json::array();
      std::string text = fmt::format("{:<36} {:<24} {:<32} {:>12} {:>10} {:>8}\n", "effect", "test",
                                     "against", "statistic", "p-value", "z");
      int significant = 0;
      for (const auto& f : d.findings) {
        significant += f.significant;
        result.json["findings"].push_back({{"effect", core::effect_name(f.kind)},
                                           {"test", f.test},
                                           {"covariate", f.covariate},
                                           {"statistic", f.result.statistic},
                                           {"p_value", f.result.p_value},
                                           {"z", f.result.z},
                                           {"significant", f.significant}});
        text += fmt::format("{:<36} {:<24} {:<32} {:>12.4g} {:>10.3g} {:>8.2f}{}\n",
                            core::effect_name(f.kind), f.test, f.covariate, f.result.statistic,
                            f.result.p_value, f.result.z, f.significant ? "  *" : "");
      }
      const bool any = significant > 0;
      result.json["named"] = any ? core::effect_name(d.findings.front().kind) : "none";
      text +=
          any ? fmt::format("* significant at 5 % family-wise (Bonferroni); the model lacks: {}\n",
                            core::effect_name(d.findings.front().kind))
              : "no finding is significant at 5 % family-wise: the model explains the data\n";
      if (any && has_covariate_extension(d.findings.front().kind)) {
        // Held-out data decide: train on the first half of the cycles, test on the rest.
        const double split = split_time(measured, 0.5);
        const ExtensionReport e = evaluate_covariate_extension(
            d.findings.front().kind, measured.slice(-1e300, split), measured.slice(split, 1e300),
            training->settings(), *window, *stride);
        result.json["extension"] = {{"effect", core::effect_name(e.effect)},
                                    {"covariate", e.covariate},
                                    {"coefficient_mm", e.coefficient},
                                    {"window", e.window},
                                    {"held_out_mae_before_mm", e.before.mean_absolute_error},
                                    {"held_out_mae_after_mm", e.after.mean_absolute_error},
                                    {"held_out_rmse_before_mm", e.before.rmse},
                                    {"held_out_rmse_after_mm", e.after.rmse},
                                    {"kept", e.kept}};
        text += fmt::format(
            "extension: + gamma * {} (gamma = {:.4g} mm per unit); held-out d hat over windows of "
            "{}: MAE {:.3f} -> {:.3f} mm (factor {:.2f}), RMSE {:.3f} -> {:.3f} mm; {}\n",
            e.covariate, e.coefficient, e.window, e.before.mean_absolute_error,
            e.after.mean_absolute_error, e.before.mean_absolute_error / e.after.mean_absolute_error,
            e.before.rmse, e.after.rmse, e.kept ? "kept" : "not kept (no held-out gain)");
      } else if (any) {
        text += "extension: none fitted for this effect yet\n";
      }
      report->write_if_requested(measured, training->settings(), result.json, !common.quiet);
      result.text = text;
      return result;
    };
  });
}

}  // namespace tofcomp::cli
