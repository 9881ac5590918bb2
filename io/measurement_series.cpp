#include "io/measurement_series.hpp"

#include <unordered_map>

namespace tofcomp::io {
namespace {

// Calls visit(beam, row, true range in force) for every row with a range.
template <typename Visit>
void visit_ranges(const MeasurementTable& table, Visit visit) {
  std::unordered_map<int, double> truth_by_beam;
  for (const MeasurementRow& row : table.rows) {
    const int beam = row.beam.value_or(0);
    if (row.true_range_mm) truth_by_beam[beam] = *row.true_range_mm;
    if (!row.range_mm) continue;
    const auto truth = truth_by_beam.find(beam);
    visit(beam, row,
          truth == truth_by_beam.end() ? std::nullopt : std::optional<double>(truth->second));
  }
}

void append_range(BeamRanges& series, const MeasurementRow& row, std::optional<double> truth) {
  series.time_s.push_back(row.time_s);
  series.range_mm.push_back(*row.range_mm);
  series.true_range_mm.push_back(truth);
  series.line.push_back(row.line);
}

TimedSamples samples_of(const MeasurementTable& table,
                        std::optional<double> MeasurementRow::*quantity) {
  TimedSamples samples;
  for (const MeasurementRow& row : table.rows) {
    if (const std::optional<double>& value = row.*quantity) {
      samples.time_s.push_back(row.time_s);
      samples.value.push_back(*value);
    }
  }
  return samples;
}

}  // namespace

BeamRanges beam_ranges(const MeasurementTable& table, int beam) {
  BeamRanges series;
  visit_ranges(table, [&](int row_beam, const MeasurementRow& row, std::optional<double> truth) {
    if (row_beam == beam) append_range(series, row, truth);
  });
  return series;
}

std::map<int, BeamRanges> ranges_by_beam(const MeasurementTable& table) {
  std::map<int, BeamRanges> series;
  visit_ranges(table, [&](int beam, const MeasurementRow& row, std::optional<double> truth) {
    append_range(series[beam], row, truth);
  });
  return series;
}

TimedSamples case_temperatures(const MeasurementTable& table) {
  return samples_of(table, &MeasurementRow::case_temp_c);
}

TimedSamples ambient_temperatures(const MeasurementTable& table) {
  return samples_of(table, &MeasurementRow::ambient_c);
}

std::vector<core::PowerChange> power_changes(const MeasurementTable& table) {
  std::vector<core::PowerChange> changes;
  bool on = true;
  for (const MeasurementRow& row : table.rows) {
    if (row.power && *row.power != on) {
      on = *row.power;
      changes.push_back({row.time_s, on});
    }
  }
  return changes;
}

}  // namespace tofcomp::io
