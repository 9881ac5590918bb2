// tofcomp thermal-fit DATA [--datasheet D.yaml]: Algorithm 1, the fit with the datasheet as a
// prior (or the paper's prediction-error fit with --free) on the training cycles, and the fit of
// Eq. 26 (and NRMSE) on the held-out cycles (§3.2, §8.1).
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "cli/progress.hpp"
#include "cli/report_format.hpp"
#include "cli/shared_options.hpp"

namespace tofcomp::cli {

void register_thermal_fit(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd =
      app.add_subcommand("thermal-fit",
                         "Identify the thermal model (Algorithm 1, then a fit with the datasheet "
                         "as a prior) on the first "
                         "cycles and report its fit (Eq. 26 and NRMSE) on the held-out cycles");
  auto data = add_data_options(*cmd);
  auto thermal = add_thermal_options(*cmd);
  auto fraction = std::make_shared<double>(0.5);
  cmd->add_option("--train-fraction", *fraction,
                  "Share of the record used for training; it ends at the nearest power-on")
      ->capture_default_str()
      ->check(between(0.05, 0.95));
  cmd->callback([&common, &run, data, thermal, fraction] {
    run = [&common, data, thermal, fraction] {
      Progress progress("thermal-fit", !common.quiet);
      const calibration::MeasuredData all = data->load();
      const double split = calibration::split_time(all, *fraction);
      const calibration::MeasuredData train = all.slice(-1e300, split);
      const calibration::MeasuredData held_out = all.slice(split, 1e300);
      progress.update(0.2, "fitting");
      const calibration::ThermalFit fit =
          calibration::fit_thermal(train, &held_out, thermal->settings());
      progress.done();
      CommandResult result;
      result.json = to_json(fit);
      result.json["split_time_s"] = split;
      result.text = thermal_fit_text(fit);
      return result;
    };
  });
}

}  // namespace tofcomp::cli
