#include "cli/measured_data_csv.hpp"

#include <fmt/format.h>

#include <limits>

#include "io/measurement_csv.hpp"
#include "io/measurement_series.hpp"
#include "io/measurement_table_builder.hpp"

namespace tofcomp::cli {

MeasuredData read_measured_data(const std::string& file, int beam,
                                std::vector<std::string>& warnings) {
  const io::MeasurementTable table = io::read_measurements_file(file);
  warnings.insert(warnings.end(), table.warnings.begin(), table.warnings.end());
  MeasuredData data;
  data.source = file;
  data.beam = beam;
  const io::BeamRanges ranges = io::beam_ranges(table, beam);
  const auto count = static_cast<Eigen::Index>(ranges.time_s.size());
  data.range_time_s = Eigen::Map<const Eigen::VectorXd>(ranges.time_s.data(), count);
  data.range_mm = Eigen::Map<const Eigen::VectorXd>(ranges.range_mm.data(), count);
  data.true_range_mm.resize(count);
  for (Eigen::Index k = 0; k < count; ++k) {
    const auto& truth = ranges.true_range_mm[static_cast<std::size_t>(k)];
    data.true_range_mm[k] = truth.value_or(0.0);
    data.has_true_range.push_back(truth.has_value());
  }
  data.range_line = ranges.line;
  const io::TimedSamples temperatures = io::case_temperatures(table);
  const auto readings = static_cast<Eigen::Index>(temperatures.time_s.size());
  data.temperature_time_s = Eigen::Map<const Eigen::VectorXd>(temperatures.time_s.data(), readings);
  data.case_c = Eigen::Map<const Eigen::VectorXd>(temperatures.value.data(), readings);
  for (const auto& change : io::power_changes(table)) {
    data.power_changes.emplace_back(change.time_s, change.on);
  }
  const io::TimedSamples ambient = io::ambient_temperatures(table);
  for (std::size_t i = 0; i < ambient.time_s.size(); ++i) {
    data.ambient.emplace_back(ambient.time_s[i], ambient.value[i]);
  }
  return data;
}

void write_twin_series(const std::string& file, const sim::Scenario& scenario,
                       const sim::TwinSeries& series) {
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
  io::write_measurements_file(file, table.finish());
}

}  // namespace tofcomp::cli
