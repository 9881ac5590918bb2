// tofcomp train DATA [--datasheet D.yaml] -o CALIBRATION.yaml: thermal identification, the
// Kalman-smoothed junction temperature and EM training (§3, §5) into a calibration file.
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "cli/progress.hpp"
#include "cli/report_format.hpp"
#include "cli/shared_options.hpp"
#include "cli/structure_format.hpp"

namespace tofcomp::cli {

void register_train(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "train",
      "Train a calibration (thermal model, basis, θ, lasing modes) on data with a "
      "known distance, and write it as a calibration file");
  auto data = add_data_options(*cmd);
  auto training = add_training_options(*cmd);
  auto output = std::make_shared<std::string>();
  cmd->add_option("-o,--output", *output, "Calibration file to write (YAML)")->required();
  auto threads = std::make_shared<int>(0);
  cmd->add_option("--threads", *threads,
                  "Fits run at once: the structure search's folds (default: one per core; the "
                  "results do not depend on it)")
      ->check(between(1, kMaxParallelism));
  cmd->callback([&common, &run, data, training, output, threads] {
    run = [&common, data, training, output, threads] {
      Progress progress("train", !common.quiet);
      const calibration::MeasuredData measured = data->load();
      calibration::TrainSettings settings = training->settings();
      settings.threads = *threads;
      const calibration::Training t = calibration::train_calibration(
          measured, settings, nullptr,
          [&](double share, const std::string& stage) { progress.update(share, stage); });
      io::write_calibration_file(*output, t.calibration);
      progress.done("wrote " + *output);
      CommandResult result;
      result.json = training_json(t);
      result.json["output"] = *output;
      result.text = thermal_fit_text(t.thermal) + choices_text(t) + calibration_text(t.calibration) +
                    "EM: " + std::to_string(t.em.iterations) + " iterations" +
                    (t.em.converged ? "" : " (cap reached)") + "\nwrote " + *output + "\n";
      return result;
    };
  });
}

}  // namespace tofcomp::cli
