// Training settings with the paper's structure as §8 prints it (an order-4 polynomial, two modes,
// the LMS 200 filter levels, the junction's dynamics the thermal fit's), fixed rather than chosen
// from the data: for tests that judge something downstream of training against Eq. 8 as printed,
// quickly. Needs tofcomp_calibration, tofcomp_io and TOFCOMP_SOURCE_ROOT.
#pragma once

#include <string>

#include "calibration/training.hpp"
#include "io/datasheet_file.hpp"

namespace tofcomp::test {

inline calibration::TrainSettings paper_structure_settings() {
  calibration::TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(std::string(TOFCOMP_SOURCE_ROOT) + "/config/lms200-datasheet.yaml");
  settings.basis = "polynomial:4";
  settings.modes = 2;
  settings.kalman_noise = core::ThermalNoise{};
  settings.junction_source = calibration::JunctionSource::CaseLog;
  return settings;
}

}  // namespace tofcomp::test
