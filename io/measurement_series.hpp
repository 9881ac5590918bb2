// What the analyses need from a measurement table, one quantity at a time, with the format's
// holding rules applied (io/README.md). Each function is one pass over the rows.
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "core/power_change.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::io {

// One beam's ranges in row order, each with the true range in force for that beam at its
// instant (set on the same row or the last earlier row of that beam that set it; nullopt before
// the first) and the line it was read from. There is no power column: a range while the power
// is 0 is an error of the format, so every range was taken with the power on.
struct BeamRanges {
  std::vector<double> time_s;
  std::vector<double> range_mm;
  std::vector<std::optional<double>> true_range_mm;
  std::vector<long> line;
};

// A quantity logged at its own instants, in row order.
struct TimedSamples {
  std::vector<double> time_s;
  std::vector<double> value;
};

// The power switching: only rows that change the power in force (on before the first change)
// are events; a row setting the power it already has is none.

BeamRanges beam_ranges(const MeasurementTable& table, int beam);

// Every beam that has a range, in one pass.
std::map<int, BeamRanges> ranges_by_beam(const MeasurementTable& table);

TimedSamples case_temperatures(const MeasurementTable& table);

TimedSamples ambient_temperatures(const MeasurementTable& table);

std::vector<core::PowerChange> power_changes(const MeasurementTable& table);

}  // namespace tofcomp::io
