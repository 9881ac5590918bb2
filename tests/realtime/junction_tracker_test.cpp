#include "realtime/junction_tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "tests/realtime/realtime_examples.hpp"

namespace tofcomp::realtime {
namespace {

// At rest with the laser on (Eq. 3 at steady state) the case is P·R2 = 12 K above the 22 °C
// ambient and the junction P·R1 = 6 K above the case.
TEST(JunctionTracker, SteadyStateIsCasePlusPowerTimesR1) {
  JunctionTracker tracker(testing::round_calibration());
  EXPECT_FALSE(tracker.at(0.0).valid);
  // The case held at its steady state for 10 time constants (64 s each), read once a second.
  for (int s = 0; s <= 640; ++s) tracker.add_case_reading(s, 34.0);
  const JunctionEstimate e = tracker.at(640.5);
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.junction_c, 40.0, 0.05);
  EXPECT_GT(e.junction_std_c, 0.0);
  EXPECT_LT(e.junction_std_c, 0.5);
  EXPECT_DOUBLE_EQ(e.case_c, 34.0);
  EXPECT_FALSE(e.stale);
}

// With the laser off the scanner cools to the ambient, the junction with it.
TEST(JunctionTracker, PowerOffSettlesOnTheCase) {
  JunctionTracker tracker(testing::round_calibration());
  tracker.set_power(0.0, false);
  for (int s = 0; s <= 640; ++s) tracker.add_case_reading(s, 22.0);
  EXPECT_NEAR(tracker.at(640.0).junction_c, 22.0, 0.05);
  // Power back on: the junction rises towards case + 6 K with its own time constant
  // (≈ 6 s here), so 3 s later it is part of the way up.
  tracker.set_power(640.0, true);
  const double after = tracker.at(643.0).junction_c;
  EXPECT_GT(after, 23.0);
  EXPECT_LT(after, 27.5);
}

// An ambient reading moves Eq. 3's t^a: with no case reading after the first, the prediction
// settles where the model puts the scanner in that room (the case P·R2 = 12 K above it, the
// junction P·R1 = 6 K above the case); without one, the calibration's 22 °C stands.
TEST(JunctionTracker, AnAmbientReadingIsTheRoomTheModelSettlesIn) {
  JunctionTracker at_calibration(testing::round_calibration());
  JunctionTracker at_reading(testing::round_calibration());
  for (JunctionTracker* t : {&at_calibration, &at_reading}) t->add_case_reading(0.0, 34.0);
  EXPECT_DOUBLE_EQ(at_reading.at(0.0).ambient_c, 22.0);
  at_reading.set_ambient(0.0, 30.0);
  // 20 case time constants of 64 s with no reading: the prediction alone.
  const JunctionEstimate calibration_room = at_calibration.at(1280.0);
  const JunctionEstimate read_room = at_reading.at(1280.0);
  EXPECT_NEAR(calibration_room.junction_c, 22.0 + 12.0 + 6.0, 0.05);
  EXPECT_NEAR(read_room.junction_c, 30.0 + 12.0 + 6.0, 0.05);
  EXPECT_DOUBLE_EQ(calibration_room.ambient_c, 22.0);
  EXPECT_DOUBLE_EQ(read_room.ambient_c, 30.0);
  EXPECT_THROW(at_reading.set_ambient(1.0, NAN), core::InvalidInput);
  EXPECT_DOUBLE_EQ(at_reading.at(1280.0).ambient_c, 30.0);  // the refused reading changed nothing
}

TEST(JunctionTracker, StaleAfterTheConfiguredSilence) {
  JunctionTrackerSettings settings;
  settings.stale_after_s = 5.0;
  JunctionTracker tracker(testing::round_calibration(), settings);
  tracker.add_case_reading(10.0, 25.0);
  EXPECT_FALSE(tracker.at(14.9).stale);
  EXPECT_TRUE(tracker.at(15.1).stale);
  EXPECT_TRUE(tracker.at(15.1).valid);  // still a prediction of the model
  // A late reading (older than the filter) is taken at the filter's time, not refused.
  tracker.add_case_reading(12.0, 25.0);
  tracker.add_case_reading(9.0, 25.0);
  EXPECT_FALSE(tracker.at(16.0).stale);
}

TEST(JunctionTracker, RefusesNonFiniteInput) {
  JunctionTracker tracker(testing::round_calibration());
  EXPECT_THROW(tracker.add_case_reading(0.0, NAN), core::InvalidInput);
  EXPECT_THROW(tracker.add_case_reading(INFINITY, 20.0), core::InvalidInput);
  JunctionTrackerSettings bad;
  bad.stale_after_s = 0.0;
  EXPECT_THROW(JunctionTracker(testing::round_calibration(), bad), core::InvalidInput);
}

// The heating rate is Eq. 3's at the estimated state: 0 at rest; when the laser goes off with
// the junction 6 K above the case it is (t^c − t^j) / (R1 C1) = −6 K / 10 s = −36 °C/min.
TEST(JunctionTracker, HeatingRateIsTheThermalModels) {
  JunctionTracker tracker(testing::round_calibration());
  for (int s = 0; s <= 640; ++s) tracker.add_case_reading(s, 34.0);
  EXPECT_NEAR(tracker.at(640.5).heating_rate_c_per_min, 0.0, 0.3);
  tracker.set_power(640.5, false);
  EXPECT_NEAR(tracker.at(640.5).heating_rate_c_per_min, -36.0, 0.5);
}

// The warm-up covariate's clock: since the clock's origin while the power has been on
// throughout, 0 while off, and from the last switch-on after it (a repeated "on" is no switch-on).
TEST(JunctionTracker, TimeSincePowerOnRestartsAtEachSwitchOn) {
  JunctionTracker tracker(testing::round_calibration());
  tracker.add_case_reading(0.0, 30.0);
  EXPECT_DOUBLE_EQ(tracker.at(100.0).time_since_power_on_s, 100.0);
  tracker.set_power(100.0, true);
  EXPECT_DOUBLE_EQ(tracker.at(150.0).time_since_power_on_s, 150.0);
  tracker.set_power(200.0, false);
  EXPECT_DOUBLE_EQ(tracker.at(250.0).time_since_power_on_s, 0.0);
  tracker.set_power(300.0, true);
  EXPECT_DOUBLE_EQ(tracker.at(300.0).time_since_power_on_s, 0.0);
  EXPECT_DOUBLE_EQ(tracker.at(342.5).time_since_power_on_s, 42.5);
}

}  // namespace
}  // namespace tofcomp::realtime
