// The twin's series (sim/twin.hpp) written as measured data, the interchange CSV of
// ../shared/docs/data-format.md: the file `tofcomp simulate` writes and every analysis reads.
#pragma once

#include <ostream>
#include <string>

#include "sim/twin.hpp"

namespace tofcomp::sim {

// Writes the twin's series as measured data, with the scenario in metadata comments.
void write_twin_measured_data(const std::string& file, const Scenario& scenario,
                              const TwinSeries& series);
// The same, to a stream (`tofcomp simulate` without -o: stdout).
void write_twin_measured_data(std::ostream& out, const Scenario& scenario,
                              const TwinSeries& series);

}  // namespace tofcomp::sim
