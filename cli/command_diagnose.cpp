// tofcomp diagnose DATA --datasheet D.yaml [--calibration C.yaml]: finds in the residuals of a
// trained model what Eq. 8 lacks (core/residual_diagnosis.hpp) and ranks the findings.
#include <fmt/format.h>

#include "cli/command.hpp"
#include "cli/progress.hpp"
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
  cmd->add_option("--calibration", *calibration,
                  "A calibration trained on these data (default: train one)")
      ->check(CLI::ExistingFile);
  cmd->callback([&common, &run, data, training, calibration] {
    run = [&common, data, training, calibration] {
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
      result.text = text;
      return result;
    };
  });
}

}  // namespace tofcomp::cli
