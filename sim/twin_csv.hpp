// The twin's series as the interchange CSV (../shared/docs/data-format.md): the measured-data
// file `tofcomp simulate` writes and every analysis reads.
#pragma once

#include <string>

#include "sim/twin.hpp"

namespace tofcomp::sim {

// Writes the twin's series as the interchange CSV, with the scenario in metadata comments.
void write_twin_series(const std::string& file, const Scenario& scenario, const TwinSeries& series);

}  // namespace tofcomp::sim
