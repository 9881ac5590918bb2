// calibration/junction_estimate: the merged grid of readings and ranges the smoother runs over
// (§3.3), and the junction at the ranges read off it.
#include "calibration/junction_estimate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/covariate_table.hpp"
#include "core/error.hpp"
#include "core/thermal_model.hpp"

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

// The beams of one record: a beam at the instants of the one before takes its smoothing; a beam
// at other instants (a range missing, no echo) is smoothed at its own.
TEST(RecordJunctions, BeamsAtTheSameInstantsShareTheSmoothingAndOthersGetTheirOwn) {
  const core::ThermalParameters thermal = core::lms200_example_parameters();
  const core::ThermalNoise noise;
  RecordJunctions junctions(thermal, noise, 22.0);
  MeasuredData beam0 = small_record();
  MeasuredData beam1 = small_record();
  beam1.beam = 1;
  beam1.range_mm = Eigen::Vector3d(2000.0, 2001.0, 2002.0);
  MeasuredData beam2 = small_record();
  beam2.beam = 2;
  beam2.range_time_s = Eigen::Vector2d(0.25, 2.75);
  beam2.range_mm = Eigen::Vector2d(3000.0, 3001.0);
  beam2.true_range_mm = Eigen::Vector2d(3000.0, 3000.0);
  beam2.has_true_range = {true, true};
  for (const MeasuredData* beam : {&beam0, &beam1, &beam2, &beam0}) {
    const SmoothedJunction expected = junction_at_ranges(*beam, thermal, noise, 22.0);
    const SmoothedJunction& got = junctions.at(*beam);
    EXPECT_EQ(got.junction_c, expected.junction_c) << "beam " << beam->beam;
    EXPECT_EQ(got.heating_rate_c_per_min, expected.heating_rate_c_per_min) << "beam " << beam->beam;
  }
}

TEST(MeasuredData, TheMedianAmbientIsTheOneLoggedAtTheRanges) {
  // small_record: the ambient 20 °C until 2 s, 25 °C after; ranges at 0.5, 1 and 2.5 s.
  EXPECT_DOUBLE_EQ(small_record().median_ambient_at_ranges(22.0), 20.0);
  MeasuredData later = small_record();
  later.range_time_s = Eigen::Vector3d(0.5, 2.5, 2.8);
  EXPECT_DOUBLE_EQ(later.median_ambient_at_ranges(22.0), 25.0);
  MeasuredData no_ambient = small_record();
  no_ambient.ambient.clear();
  EXPECT_DOUBLE_EQ(no_ambient.median_ambient_at_ranges(22.0), 22.0);
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

// A record that follows Eq. 3 exactly (the datasheet-like example, junction lag R1 C1 = 12 s):
// the laser on from cold at 0 s, off at 300 s, on again at 400 s until 600 s; the case read
// every 0.5 s, rounded as a sensor rounds, a range every 0.25 s while the laser is on.
MeasuredData exact_power_on_record() {
  const core::ThermalParameters thermal = core::lms200_example_parameters();
  constexpr double kAmbientC = 22.0;
  constexpr double kEndS = 600.0;
  MeasuredData data;
  data.source = "exact";
  data.power_changes = {core::PowerChange{300.0, false}, core::PowerChange{400.0, true}};
  data.ambient = {{0.0, kAmbientC}};
  const int readings = static_cast<int>(kEndS / 0.5);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(readings, 0.0, kEndS - 0.5);
  Eigen::VectorXd on(readings);
  for (int i = 0; i < readings; ++i) on[i] = data.power_on_fraction(times[i], times[i] + 0.5);
  data.temperature_time_s = times;
  // Read as a TMP102 reads it, in steps of 1/16 °C.
  constexpr double kSensorStepC = 0.0625;
  data.case_c = (core::simulate_at_times(thermal, Eigen::Vector2d(kAmbientC, kAmbientC), times, on,
                                         Eigen::VectorXd::Constant(readings, kAmbientC))
                     .case_c.array() /
                 kSensorStepC)
                    .round() *
                kSensorStepC;
  std::vector<double> range_times;
  for (double t = 0.125; t < kEndS; t += 0.25) {
    if (data.power_on_at(t)) range_times.push_back(t);
  }
  const auto n = static_cast<Eigen::Index>(range_times.size());
  data.range_time_s = Eigen::Map<const Eigen::VectorXd>(range_times.data(), n);
  data.range_mm = Eigen::VectorXd::Constant(n, 1000.0);
  data.true_range_mm = data.range_mm;
  data.has_true_range.assign(range_times.size(), true);
  return data;
}

// The true junction's rate: central differences of Eq. 3 simulated finely (ZOH steps of 1 ms
// from rest at the ambient), independent of the model's formula.
class TrueJunctionRate {
 public:
  explicit TrueJunctionRate(const MeasuredData& data) {
    const int steps =
        static_cast<int>(std::lround(data.range_time_s.maxCoeff() / kStepS)) + 2 * kHalf + 1;
    const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(steps, 0.0, (steps - 1) * kStepS);
    Eigen::VectorXd on(steps);
    for (int i = 0; i < steps; ++i) on[i] = data.power_on_at(times[i]) ? 1.0 : 0.0;
    junction_c_ =
        core::simulate_at_times(core::lms200_example_parameters(), Eigen::Vector2d(22.0, 22.0),
                                times, on, Eigen::VectorXd::Constant(steps, 22.0))
            .junction_c;
  }
  double at(double time_s) const {
    const auto k = static_cast<Eigen::Index>(std::lround(time_s / kStepS));
    return (junction_c_[k + kHalf] - junction_c_[k - kHalf]) / (2 * kHalf * kStepS);
  }

 private:
  static constexpr double kStepS = 0.001;
  static constexpr int kHalf = 10;
  Eigen::VectorXd junction_c_;
};

TEST(SmoothedJunction, TheHeatingRateAfterAPowerOnIsTheJunctionsOwn) {
  const MeasuredData data = exact_power_on_record();
  const core::ThermalParameters thermal = core::lms200_example_parameters();
  const SmoothedJunction junction = junction_at_ranges(data, thermal, core::ThermalNoise{}, 22.0);
  ASSERT_EQ(junction.heating_rate_c_per_min.size(), data.range_time_s.size());
  const Eigen::VectorXd slope = 60.0 * core::local_rate(data.range_time_s, junction.junction_c,
                                                        core::kHeatingRateHalfWindowS);
  // The first minute after each power-on, where the junction settles on the case (P R1 = 2 K in
  // R1 C1 = 12 s: up to P / C1 = 10 °C/min) and the rate is largest.
  const TrueJunctionRate truth_of(data);
  double peak = 0.0, model_error = 0.0, slope_error = 0.0;
  for (Eigen::Index k = 0; k < data.range_time_s.size(); ++k) {
    const double t = data.range_time_s[k];
    const double since_on = t - data.last_power_on_at(t);
    if (since_on > 60.0 || t < 1.0) continue;
    const double truth = 60.0 * truth_of.at(t);
    peak = std::max(peak, std::abs(truth));
    model_error = std::max(model_error, std::abs(junction.heating_rate_c_per_min[k] - truth));
    slope_error = std::max(slope_error, std::abs(slope[k] - truth));
  }
  EXPECT_GT(peak, 5.0);  // °C/min: the transient is there
  // The smoothed state's own error from readings in steps of 1/16 °C (0.59 of a peak of
  // 9.87 °C/min when written; 0 with exact readings).
  EXPECT_LT(model_error, 0.1 * peak);
  // A slope over ±30 s, what the covariate was before, is off by two thirds of the peak there
  // (6.51 °C/min).
  EXPECT_GT(slope_error, 0.3 * peak);
}

}  // namespace
}  // namespace tofcomp::calibration
