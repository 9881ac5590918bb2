#include "calibration/measured_data_reader.hpp"

#include "io/measured_data_csv.hpp"
#include "io/measurement_series.hpp"
#include "io/measurement_table_builder.hpp"

namespace tofcomp::calibration {

MeasuredData read_measured_data(const std::string& file, int beam,
                                std::vector<std::string>& warnings) {
  const io::MeasurementTable table = io::read_measured_data_file(file);
  warnings.insert(warnings.end(), table.warnings.begin(), table.warnings.end());
  return measured_data_from_table(table, file, beam);
}

MeasuredData measured_data_from_table(const io::MeasurementTable& table, const std::string& source,
                                      int beam) {
  MeasuredData data;
  data.source = source;
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
  data.power_changes = io::power_changes(table);
  const io::TimedSamples ambient = io::ambient_temperatures(table);
  for (std::size_t i = 0; i < ambient.time_s.size(); ++i) {
    data.ambient.emplace_back(ambient.time_s[i], ambient.value[i]);
  }
  return data;
}

}  // namespace tofcomp::calibration
