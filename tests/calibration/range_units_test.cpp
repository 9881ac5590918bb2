// The ranges' step (calibration/measured_data.hpp): ranges in the LMS 200's cm units, all whole
// multiples of 10 mm, are refused by training with a message that names the file, the step and
// the fix, before any fit (on such ranges the fits made a mode of σ 0.29 mm that took 91 % of
// them); ranges in mm are trained as before, and a logger's averaged ranges are not taken for
// rounded ones.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "calibration/measured_data.hpp"
#include "calibration/training.hpp"
#include "core/error.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/paper_structure_settings.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

MeasuredData default_record() {
  sim::Scenario scenario =
      sim::load_scenario_file(std::string(TOFCOMP_SOURCE_ROOT) + "/config/scenarios/default.yaml");
  return test::twin_measured_data(scenario);
}

TEST(RangeUnits, RangesInCentimetresAreRefusedNamingTheStepAndTheFix) {
  MeasuredData data = default_record();
  data.source = "cm.csv";
  for (Eigen::Index k = 0; k < data.range_mm.size(); ++k) {
    data.range_mm[k] =
        kCentimetreRangeStepMm * std::round(data.range_mm[k] / kCentimetreRangeStepMm);
  }
  try {
    train_calibration(data, test::paper_structure_settings());
    FAIL() << "ranges in cm were trained";
  } catch (const core::InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cm.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("multiples of 10 mm"), std::string::npos) << what;
    EXPECT_NE(what.find("link.units: mm"), std::string::npos) << what;
  }
}

TEST(RangeUnits, RangesInMillimetresAreRoundedToOneMillimetre) {
  MeasuredData data = default_record();
  EXPECT_NO_THROW(data.require_millimetre_ranges());
  EXPECT_EQ(data.range_resolution_mm(), kRangeResolutionMm);
  // A logger that averaged ranges: not on the lattice, so no rounding is assumed.
  data.range_mm[3] += 0.25;
  EXPECT_EQ(data.range_resolution_mm(), 0.0);
  EXPECT_NO_THROW(data.require_millimetre_ranges());
}

TEST(RangeUnits, AFewRangesOnWholeCentimetresAreNotJudged) {
  MeasuredData data = default_record();
  MeasuredData few = data.with_ranges({0, 1, 2, 3, 4});
  for (Eigen::Index k = 0; k < few.range_mm.size(); ++k) few.range_mm[k] = 3000.0 + 10.0 * k;
  EXPECT_NO_THROW(few.require_millimetre_ranges());
}

}  // namespace
}  // namespace tofcomp::calibration
