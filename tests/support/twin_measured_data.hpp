// The digital twin's record of a scenario as a user's measured data: simulated, written as the
// interchange CSV and read back by the calibration library's reader (beam 0), the path a user's
// file takes. The file is the process's own (its pid and a counter in the name, so that test
// programs run in parallel never share one) and is removed once read. Needs tofcomp_sim and
// tofcomp_calibration.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "calibration/measured_data_reader.hpp"
#include "sim/twin_csv.hpp"

namespace tofcomp::test {

inline calibration::MeasuredData twin_measured_data(const sim::Scenario& scenario) {
  static std::atomic<int> files{0};
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("tofcomp-twin-" + std::to_string(::getpid()) + "-" + std::to_string(files++) + ".csv");
  sim::write_twin_measured_data(file.string(), scenario, sim::simulate_series(scenario));
  std::vector<std::string> warnings;
  calibration::MeasuredData data = calibration::read_measured_data(file.string(), 0, warnings);
  std::filesystem::remove(file);
  return data;
}

}  // namespace tofcomp::test
