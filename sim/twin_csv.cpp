#include "sim/twin_csv.hpp"

#include <fmt/format.h>

#include <limits>

#include "io/measured_data_csv.hpp"
#include "io/measurement_table_builder.hpp"

namespace tofcomp::sim {

namespace {

io::MeasurementTable twin_table(const Scenario& scenario, const TwinSeries& series) {
  io::MeasurementTableBuilder table;
  table.add_metadata("source", "tofcomp digital twin");
  table.add_metadata("scenario", scenario.name);
  table.add_metadata("seed", std::to_string(scenario.seed));
  table.add_metadata("target", fmt::format("{} mm", scenario.true_range_mm));
  table.add_metadata("sensor_resolution_c", fmt::format("{}", scenario.sensor.resolution_c));
  const bool several_beams = scenario.scanner.beams > 1;
  std::vector<bool> truth_written(static_cast<std::size_t>(scenario.scanner.beams), false);
  // Merge the three event streams in time; at one instant: power change, reading, range.
  std::size_t p = 0, t = 0, r = 0;
  const double inf = std::numeric_limits<double>::infinity();
  while (p < series.power_changes.size() || t < series.temperatures.size() ||
         r < series.ranges.size()) {
    const double tp = p < series.power_changes.size() ? series.power_changes[p].time_s : inf;
    const double tt = t < series.temperatures.size() ? series.temperatures[t].time_s : inf;
    const double tr = r < series.ranges.size() ? series.ranges[r].time_s : inf;
    io::MeasurementRow row;
    if (tp <= tt && tp <= tr) {
      row.time_s = tp;
      row.power = series.power_changes[p++].on;
    } else if (tt <= tr) {
      const auto& reading = series.temperatures[t++];
      row.time_s = reading.time_s;
      row.case_temp_c = reading.case_c;
      row.ambient_c = reading.ambient_c;
    } else {
      const auto& range = series.ranges[r++];
      row.time_s = range.time_s;
      row.range_mm = range.range_mm;
      if (several_beams) row.beam = range.beam;
      if (!truth_written[static_cast<std::size_t>(range.beam)]) {
        row.true_range_mm = range.true_range_mm;
        truth_written[static_cast<std::size_t>(range.beam)] = true;
      }
    }
    table.append(row);
  }
  return table.finish();
}

}  // namespace

void write_twin_measured_data(const std::string& file, const Scenario& scenario,
                              const TwinSeries& series) {
  io::write_measured_data_file(file, twin_table(scenario, series));
}

void write_twin_measured_data(std::ostream& out, const Scenario& scenario,
                              const TwinSeries& series) {
  io::write_measured_data(out, twin_table(scenario, series), "stdout");
}

}  // namespace tofcomp::sim
