#include "cli/measured_data_csv.hpp"

#include <fmt/format.h>

#include <limits>

#include "io/interchange_csv.hpp"

namespace tofcomp::cli {

MeasuredData read_measured_data(const std::string& file, int beam,
                                std::vector<std::string>& warnings) {
  const io::MeasurementTable table = io::read_measurements_file(file);
  warnings.insert(warnings.end(), table.warnings.begin(), table.warnings.end());
  MeasuredData data;
  data.source = file;
  data.beam = beam;
  std::vector<double> range_time, range, truth, temp_time, temp;
  std::optional<double> true_range;  // of this beam, holding until set again
  bool power = true;
  for (const auto& row : table.rows) {
    const bool this_beam = row.beam.value_or(0) == beam;
    if (row.true_range_mm && this_beam) true_range = row.true_range_mm;
    if (row.power && (*row.power == 1) != power) {
      power = *row.power == 1;
      data.power_changes.emplace_back(row.time_s, power);
    }
    if (row.ambient_c) data.ambient.emplace_back(row.time_s, *row.ambient_c);
    if (row.case_temp_c) {
      temp_time.push_back(row.time_s);
      temp.push_back(*row.case_temp_c);
    }
    if (row.range_mm && this_beam) {
      range_time.push_back(row.time_s);
      range.push_back(*row.range_mm);
      truth.push_back(true_range.value_or(0.0));
      data.has_true_range.push_back(true_range.has_value());
      data.range_line.push_back(row.line);
    }
  }
  auto to_vector = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  };
  data.range_time_s = to_vector(range_time);
  data.range_mm = to_vector(range);
  data.true_range_mm = to_vector(truth);
  data.temperature_time_s = to_vector(temp_time);
  data.case_c = to_vector(temp);
  return data;
}

void write_twin_series(const std::string& file, const sim::Scenario& scenario,
                       const sim::TwinSeries& series) {
  io::MeasurementTable table;
  table.metadata = {{"source", "tofcomp digital twin"},
                    {"scenario", scenario.name},
                    {"seed", std::to_string(scenario.seed)},
                    {"target", fmt::format("{} mm", scenario.true_range_mm)},
                    {"sensor_resolution_c", fmt::format("{}", scenario.sensor.resolution_c)}};
  table.columns = {"time_s", "range_mm", "case_temp_c", "power", "ambient_c", "true_range_mm"};
  const bool several_beams = scenario.scanner.beams > 1;
  if (several_beams) table.columns.insert(table.columns.begin() + 1, "beam");
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
      row.power = series.power_changes[p++].on ? 1 : 0;
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
    table.rows.push_back(row);
  }
  io::write_measurements_file(file, table);
}

}  // namespace tofcomp::cli
