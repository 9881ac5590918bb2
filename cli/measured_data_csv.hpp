// Between the interchange CSV (io/measurement_csv.hpp, ../shared/docs/data-format.md) and the
// analyses' MeasuredData, and from the twin's series to the CSV.
#pragma once

#include <string>
#include <vector>

#include "cli/measured_data.hpp"
#include "sim/twin.hpp"

namespace tofcomp::cli {

// One beam of a measured-data file. Warnings (unknown columns) are appended to `warnings`.
MeasuredData read_measured_data(const std::string& file, int beam,
                                std::vector<std::string>& warnings);

// Writes the twin's series as the interchange CSV, with the scenario in metadata comments.
void write_twin_series(const std::string& file, const sim::Scenario& scenario,
                       const sim::TwinSeries& series);

}  // namespace tofcomp::cli
