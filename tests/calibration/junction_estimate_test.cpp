// calibration/junction_estimate: the merged grid of readings and ranges the smoother runs over
// (§3.3), and the junction at the ranges read off it.
#include "calibration/junction_estimate.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

// Readings at 0, 1, 2, 3 s; ranges at 0.5, 1 (the same instant as a reading), 2.5 s; the power
// on until 1.5 s, off after; an ambient logged at 20 °C, then 25 °C from 2 s.
MeasuredData small_record() {
  MeasuredData data;
  data.source = "small";
  data.temperature_time_s = Eigen::Vector4d(0.0, 1.0, 2.0, 3.0);
  data.case_c = Eigen::Vector4d(30.0, 30.5, 31.0, 31.5);
  data.range_time_s = Eigen::Vector3d(0.5, 1.0, 2.5);
  data.range_mm = Eigen::Vector3d(1000.0, 1001.0, 1002.0);
  data.true_range_mm = Eigen::Vector3d(1000.0, 1000.0, 1000.0);
  data.has_true_range = {true, true, true};
  data.power_changes = {core::PowerChange{1.5, false}};
  data.ambient = {{0.0, 20.0}, {2.0, 25.0}};
  return data;
}

TEST(ThermalRecordGrid, MergesReadingsAndRangesInTimeReadingsFirstAtATie) {
  const ThermalRecordGrid grid = thermal_record_grid(small_record(), 22.0);
  // 0 r, 0.5 k, 1 r, 1 k, 2 r, 2.5 k, 3 r.
  ASSERT_EQ(grid.time_s.size(), 7);
  const Eigen::VectorXd expected_time = (Eigen::VectorXd(7) << 0, 0.5, 1, 1, 2, 2.5, 3).finished();
  EXPECT_EQ(grid.time_s, expected_time);
  const std::vector<bool> expected_measured{true, false, true, false, true, false, true};
  EXPECT_EQ(grid.measured, expected_measured);
  EXPECT_EQ(grid.range_in_grid, Eigen::Vector3i(1, 3, 5));
  EXPECT_DOUBLE_EQ(grid.reading_c[2], 30.5);
  EXPECT_DOUBLE_EQ(grid.reading_c[4], 31.0);
  EXPECT_DOUBLE_EQ(grid.first_case_c, 30.0);
}

TEST(ThermalRecordGrid, HoldsEachIntervalsPowerShareAndTheLoggedAmbient) {
  const ThermalRecordGrid grid = thermal_record_grid(small_record(), 22.0);
  // On through [0, 1) and [1, 1), half of [1, 2), off after; the last instant off.
  EXPECT_DOUBLE_EQ(grid.power_on[0], 1.0);
  EXPECT_DOUBLE_EQ(grid.power_on[1], 1.0);
  EXPECT_DOUBLE_EQ(grid.power_on[3], 0.5);
  EXPECT_DOUBLE_EQ(grid.power_on[4], 0.0);
  EXPECT_DOUBLE_EQ(grid.power_on[6], 0.0);
  EXPECT_DOUBLE_EQ(grid.ambient_c[3], 20.0);
  EXPECT_DOUBLE_EQ(grid.ambient_c[4], 25.0);
  // Without a logged ambient, the fallback everywhere.
  MeasuredData no_ambient = small_record();
  no_ambient.ambient.clear();
  EXPECT_TRUE((thermal_record_grid(no_ambient, 22.0).ambient_c.array() == 22.0).all());
}

TEST(ThermalRecordGrid, TheJunctionAtEachRangeIsTheSmoothedHistoryAtItsInstant) {
  const MeasuredData data = small_record();
  const core::ThermalParameters thermal = core::lms200_example_parameters();
  const core::ThermalNoise noise;
  const ThermalRecordGrid grid = thermal_record_grid(data, 22.0);
  const SmoothedJunction junction = junction_at_ranges(grid, thermal, noise);
  ASSERT_EQ(junction.junction_c.size(), 3);
  for (Eigen::Index k = 0; k < 3; ++k) {
    EXPECT_EQ(junction.junction_c[k], junction.history_junction_c[grid.range_in_grid[k]]);
  }
  // The one-call form smooths the same grid.
  EXPECT_EQ(junction_at_ranges(data, thermal, noise, 22.0).junction_c, junction.junction_c);
}

TEST(ThermalRecordGrid, ARecordWithoutCaseReadingsIsRefusedByName) {
  MeasuredData data = small_record();
  data.temperature_time_s.resize(0);
  data.case_c.resize(0);
  try {
    thermal_record_grid(data, 22.0);
    FAIL() << "no error";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("small: no case_temp_c readings"), std::string::npos);
  }
}

}  // namespace
}  // namespace tofcomp::calibration
