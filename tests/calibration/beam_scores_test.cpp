// tofcomp test's scoring (calibration/beam_scores.hpp): every beam with a reference is scored,
// a beam without one is named and left out, and a window holding a range that is not still (an
// object passing through the beam) is left out and counted, not scored against a reference that
// formally holds over it.
#include <gtest/gtest.h>

#include <random>

#include "calibration/beam_scores.hpp"
#include "calibration/measured_data_reader.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::test {
namespace {

constexpr double kSeconds = 3000.0;   // one range a second per beam: five still episodes' worth
constexpr double kCaseC = 25.0;
constexpr Eigen::Index kWindow = 200;
constexpr double kObjectFrom = 1500.0;  // an object 1.5 m in front of beam 1's wall
constexpr int kObjectRanges = 100;

core::Calibration shipped_calibration() {
  return io::read_calibration_file(std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml");
}

// Beams 0 and 1 see walls at 3 m and 5 m with their references; beam 1 is crossed by an object
// for kObjectRanges seconds; beam 2 has no reference. Ranges scatter by 2 mm about the wall.
io::MeasurementTable scene() {
  io::MeasurementTable t;
  t.columns = {"time_s", "range_mm", "beam", "case_temp_c", "true_range_mm"};
  std::mt19937 rng(56);
  std::normal_distribution<double> noise(0.0, 2.0);
  for (int s = 0; s < static_cast<int>(kSeconds); ++s) {
    const double time = s;
    t.rows.push_back({.time_s = time, .case_temp_c = kCaseC});
    for (int beam = 0; beam < 3; ++beam) {
      const double wall = 3000.0 + 2000.0 * beam;
      const bool object =
          beam == 1 && time >= kObjectFrom && time < kObjectFrom + kObjectRanges;
      io::MeasurementRow row{.time_s = time,
                             .range_mm = std::round((object ? wall - 1500.0 : wall) + noise(rng)),
                             .beam = beam};
      if (beam < 2) row.true_range_mm = wall;
      t.rows.push_back(row);
    }
  }
  return t;
}

TEST(BeamScores, EveryBeamWithAReferenceIsScoredAndAPassingObjectsWindowsAreLeftOut) {
  const core::Calibration c = shipped_calibration();
  const calibration::BeamScores scores =
      calibration::score_beams(scene(), "scene", c, std::nullopt, {kWindow}, 1);
  ASSERT_EQ(scores.beams.size(), 2u);
  EXPECT_EQ(scores.beams_without_reference, std::vector<int>{2});
  const auto all_windows = static_cast<Eigen::Index>(kSeconds) - kWindow + 1;
  // Every window that holds one of the object's ranges is left out: those starting up to
  // kWindow - 1 before it and within it.
  const calibration::WindowEvaluation& crossed = scores.beams[1].windows.front();
  EXPECT_GE(scores.beams[1].set_apart, kObjectRanges);
  EXPECT_GE(crossed.windows_left_out, kObjectRanges + kWindow - 1);
  EXPECT_EQ(static_cast<Eigen::Index>(crossed.estimates.start.size()) + crossed.windows_left_out,
            all_windows);
  // The wall alone: (almost) nothing set apart, and the scored windows are near the reference.
  const calibration::WindowEvaluation& clear = scores.beams[0].windows.front();
  EXPECT_LT(scores.beams[0].set_apart, static_cast<long>(kSeconds / 100));
  EXPECT_LT(crossed.em.mean_absolute_error, 5.0);
  // Pooled: the windows of both beams, and the moments over all of them.
  const calibration::WindowEvaluation& pooled = scores.pooled.front();
  EXPECT_EQ(pooled.estimates.start.size(),
            clear.estimates.start.size() + crossed.estimates.start.size());
  EXPECT_EQ(pooled.windows_left_out, clear.windows_left_out + crossed.windows_left_out);
  EXPECT_EQ(pooled.em.count, clear.em.count + crossed.em.count);
  EXPECT_EQ(pooled.em_inside_trained.count + pooled.em_beyond_trained.count, pooled.em.count);
}

TEST(BeamScores, OneBeamWhenNamedAndAClearErrorWithoutAReference) {
  const core::Calibration c = shipped_calibration();
  const io::MeasurementTable t = scene();
  EXPECT_EQ(calibration::score_beams(t, "scene", c, 0, {kWindow}, 10).beams.size(), 1u);
  try {
    calibration::score_beams(t, "scene", c, 2, {kWindow}, 10);
    FAIL() << "a beam without a reference was scored";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("no beam has a reference"), std::string::npos) << e.what();
  }
  EXPECT_THROW(calibration::score_beams(t, "scene", c, 7, {kWindow}, 10), core::InvalidInput);
}

// The windows a mask excludes, counted exactly: a block of m ranges inside the record takes the
// m + W - 1 windows that overlap it.
TEST(WindowEvaluation, AWindowHoldingARangeNotCountedIsLeftOut) {
  const core::Calibration c = shipped_calibration();
  const calibration::MeasuredData data = calibration::measured_data_from_table(scene(), "scene", 0);
  const calibration::Compensation compensation = calibration::compensate(data, c);
  std::vector<bool> counted(static_cast<std::size_t>(data.range_mm.size()), true);
  constexpr int kFrom = 1000, kBlock = 37;
  for (int k = kFrom; k < kFrom + kBlock; ++k) counted[static_cast<std::size_t>(k)] = false;
  const auto e = calibration::evaluate_windows(data, c, compensation, {kWindow}, 1, {}, counted);
  EXPECT_EQ(e.front().windows_left_out, kBlock + kWindow - 1);
  for (const Eigen::Index start : e.front().estimates.start) {
    EXPECT_TRUE(start + kWindow <= kFrom || start >= kFrom + kBlock) << start;
  }
  EXPECT_THROW(calibration::evaluate_windows(data, c, compensation, {kWindow}, 1, {},
                                             std::vector<bool>(3, true)),
               core::InvalidInput);
  // Nothing counted: every window left out, and no error stated (not a failure).
  const auto none = calibration::evaluate_windows(
      data, c, compensation, {kWindow}, 1, {},
      std::vector<bool>(static_cast<std::size_t>(data.range_mm.size()), false));
  EXPECT_EQ(none.front().windows_left_out, static_cast<Eigen::Index>(kSeconds) - kWindow + 1);
  EXPECT_EQ(none.front().em.count, 0);
}

// Inside and beyond judged against another calibration's band: a band that ends below the
// record's junction puts every window beyond it; the calibration's own band (which holds the
// record) puts none there.
TEST(WindowEvaluation, InsideAndBeyondAreJudgedAgainstTheBandGiven) {
  const core::Calibration c = shipped_calibration();
  const calibration::MeasuredData data = calibration::measured_data_from_table(scene(), "scene", 0);
  const calibration::Compensation compensation = calibration::compensate(data, c);
  core::MeasurementModel band = c.model;
  band.trained_junction_c = core::TemperatureRange{compensation.junction.junction_c.minCoeff() - 10.0,
                                                   compensation.junction.junction_c.minCoeff() - 5.0};
  const auto against_band =
      calibration::evaluate_windows(data, c, compensation, {kWindow}, 10, {}, {}, &band);
  EXPECT_EQ(against_band.front().em_beyond_trained.count, against_band.front().em.count);
  band.trained_junction_c = core::TemperatureRange{compensation.junction.junction_c.minCoeff() - 1.0,
                                                   compensation.junction.junction_c.maxCoeff() + 1.0};
  const auto inside_band =
      calibration::evaluate_windows(data, c, compensation, {kWindow}, 10, {}, {}, &band);
  EXPECT_EQ(inside_band.front().em_inside_trained.count, inside_band.front().em.count);
}

}  // namespace
}  // namespace tofcomp::test
