// tofcomp simulate SCENARIO [-o DATA.csv]: plays a twin scenario and writes the measured data,
// to the file or, without -o, to stdout (its summary then goes to stderr).
#include <cstdio>
#include <iostream>

#include "cli/command.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "sim/scenario_yaml.hpp"
#include "sim/twin_csv.hpp"

namespace tofcomp::cli {

void register_simulate(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Play a twin scenario (config/scenarios/*.yaml) and write the measured data "
      "as the interchange CSV");
  auto scenario = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  cmd->add_option("scenario", *scenario, "Scenario YAML file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", *output, "CSV file to write (default: stdout)")->type_name("FILE");
  cmd->callback([&common, &run, scenario, output] {
    run = [&common, scenario, output] {
      const bool to_stdout = output->empty();
      if (to_stdout && common.json) {
        throw core::InvalidInput("--json needs -o FILE: without it the CSV goes to stdout");
      }
      const sim::Scenario s = sim::load_scenario_file(*scenario);
      Progress progress("simulate " + s.name, !common.quiet);
      const sim::TwinSeries series = sim::simulate_series(s, [&](double f) { progress.update(f); });
      if (to_stdout) {
        sim::write_twin_measured_data(std::cout, s, series);
        std::cout.flush();
      } else {
        sim::write_twin_measured_data(*output, s, series);
      }
      progress.done(std::to_string(series.ranges.size()) + " ranges");
      double lo = 1e300, hi = -1e300;
      for (const auto& r : series.ranges) {
        lo = std::min(lo, r.junction_c);
        hi = std::max(hi, r.junction_c);
      }
      CommandResult result;
      result.json = {{"scenario", s.name},
                     {"output", to_stdout ? "-" : *output},
                     {"ranges", series.ranges.size()},
                     {"temperature_readings", series.temperatures.size()},
                     {"power_changes", series.power_changes.size()},
                     {"no_echo", series.no_echo_count},
                     {"duration_s", s.duration_s()}};
      if (!series.ranges.empty()) {
        result.json["junction_min_c"] = lo;
        result.json["junction_max_c"] = hi;
      }
      char text[512];
      std::snprintf(text, sizeof text,
                    "wrote %s: %zu ranges, %zu case readings, %zu power changes over %.0f s "
                    "(junction %.2f-%.2f °C; %d no-echo readings not recorded)\n",
                    to_stdout ? "stdout" : output->c_str(), series.ranges.size(),
                    series.temperatures.size(), series.power_changes.size(), s.duration_s(), lo, hi,
                    series.no_echo_count);
      result.text = text;
      if (to_stdout) {
        // stdout holds the CSV: the summary goes with the progress.
        if (!common.quiet) std::fputs(text, stderr);
        result.streamed = true;
      }
      return result;
    };
  });
}

}  // namespace tofcomp::cli
