// From the interchange CSV (io/measured_data_csv.hpp, ../shared/docs/data-format.md) to the
// analyses' MeasuredData.
#pragma once

#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::calibration {

// One beam of a measured-data file. Warnings (unknown columns) are appended to `warnings`.
MeasuredData read_measured_data(const std::string& file, int beam,
                                std::vector<std::string>& warnings);

// One beam of a table already read; `source` names it.
MeasuredData measured_data_from_table(const io::MeasurementTable& table, const std::string& source,
                                      int beam);

}  // namespace tofcomp::calibration
