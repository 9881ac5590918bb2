// A tofcompd scan as LaserScan fields (bridges/ros2/laser_scan.hpp) against values worked out by
// hand from the LMS 200's sweep (docs/protocol.md, "Time"): angles with 90° ahead, REP 117's
// special ranges, the first ray's stamp, time_increment spreading the rays' span over the beams.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bridges/ros2/dds_publisher.hpp"
#include "bridges/ros2/laser_scan.hpp"
#include "core/error.hpp"

namespace tofcomp::bridges::ros2 {
namespace {

constexpr double kTurnNs = 1e9 / 75.0;  // the LMS 200's mirror turns 75 times a second
constexpr std::int64_t kFirstRayNs = 1795624951000000000;

// A scan of `count` beams from 0° at `resolution_deg`, interlacing `turns` turns, every
// compensated range 3000.5 mm.
client::Scan scan_of(std::uint32_t count, double resolution_deg, std::uint32_t turns) {
  client::Scan scan;
  scan.info.sequence = 7;
  scan.info.timestamp_ns = kFirstRayNs + 35000000;
  scan.info.start_angle_deg = 0.0;
  scan.info.resolution_deg = resolution_deg;
  scan.info.beam_count = count;
  scan.info.first_ray_ns = kFirstRayNs;
  scan.info.turn_period_ns = kTurnNs;
  scan.info.ray_interval_ns = kTurnNs * turns * resolution_deg / 360.0;
  scan.info.interlaced_turns = turns;
  for (std::uint32_t i = 0; i < count; ++i) {
    client::Beam beam{};
    beam.index = i;
    beam.compensated_mm = 3000.5;
    scan.beams.push_back(beam);
  }
  return scan;
}

TEST(Ros2LaserScan, AnglesRunFromRightToLeftWithNinetyDegreesAhead) {
  const LaserScanValues s = laser_scan_from(scan_of(361, 0.5, 2));
  EXPECT_FLOAT_EQ(s.angle_min, static_cast<float>(-std::numbers::pi / 2));
  EXPECT_FLOAT_EQ(s.angle_max, static_cast<float>(std::numbers::pi / 2));
  EXPECT_FLOAT_EQ(s.angle_increment, static_cast<float>(std::numbers::pi / 360));
  EXPECT_FLOAT_EQ(s.range_min, 0.0f);
  EXPECT_FLOAT_EQ(s.range_max, 81.91f);
  ASSERT_EQ(s.ranges.size(), 361u);
  EXPECT_FLOAT_EQ(s.ranges[180], 3.0005f);
}

TEST(Ros2LaserScan, OneTurnScanHasItsRayIntervalAsTimeIncrement) {
  const LaserScanValues s = laser_scan_from(scan_of(181, 1.0, 1));
  EXPECT_EQ(s.stamp_ns, kFirstRayNs);
  EXPECT_FLOAT_EQ(s.time_increment, static_cast<float>(kTurnNs / 360 / 1e9));
  EXPECT_FLOAT_EQ(s.scan_time, static_cast<float>(1.0 / 75));
}

TEST(Ros2LaserScan, InterlacedScanSpreadsItsRaysSpanOverTheBeams) {
  // 0.5°: turn 0 measures the even beams, turn 1 the odd ones; the last ray is beam 359's,
  // one turn and 179 ray intervals (T/360 each) after beam 0's: T × 539/360 over 360 steps.
  const LaserScanValues s = laser_scan_from(scan_of(361, 0.5, 2));
  EXPECT_FLOAT_EQ(s.time_increment, static_cast<float>(kTurnNs * 539 / 360 / 360 / 1e9));
  EXPECT_FLOAT_EQ(s.scan_time, static_cast<float>(2.0 / 75));
}

TEST(Ros2LaserScan, UnknownRayTimesFallBackToTheArrival) {
  client::Scan scan = scan_of(181, 1.0, 1);
  scan.info.interlaced_turns = 0;
  const LaserScanValues s = laser_scan_from(scan);
  EXPECT_EQ(s.stamp_ns, scan.info.timestamp_ns);
  EXPECT_EQ(s.time_increment, 0.0f);
  EXPECT_EQ(s.scan_time, 0.0f);
}

TEST(Ros2LaserScan, SpecialRangesFollowRep117) {
  client::Beam beam{};
  beam.compensated_mm = 1234.0;
  EXPECT_FLOAT_EQ(ros_range(beam), 1.234f);
  beam.flags = TOFCOMP_FLAG_NO_ECHO;
  beam.compensated_mm = std::nan("");
  EXPECT_TRUE(std::isinf(ros_range(beam)) && ros_range(beam) > 0);  // no return: +Inf
  beam.flags = TOFCOMP_FLAG_UNCALIBRATED;
  EXPECT_TRUE(std::isnan(ros_range(beam)));  // no compensated range: NaN
  beam.flags = TOFCOMP_FLAG_OUTLIER;  // flagged, yet a range: published, counted in diagnostics
  beam.compensated_mm = 2000.0;
  EXPECT_FLOAT_EQ(ros_range(beam), 2.0f);
}

TEST(Ros2LaserScan, APartialScanIsRefused) {
  client::Scan scan = scan_of(361, 0.5, 2);
  scan.beams.pop_back();
  EXPECT_THROW(laser_scan_from(scan), core::InvalidInput);
  scan = scan_of(361, 0.5, 2);
  scan.info.resolution_deg = 0.0;
  EXPECT_THROW(laser_scan_from(scan), core::InvalidInput);
}

TEST(Ros2LaserScan, RosTimeSplitsNanosecondsWithFloor) {
  EXPECT_EQ(ros_time(kFirstRayNs).sec, 1795624951);
  EXPECT_EQ(ros_time(kFirstRayNs + 999999999).nanosec, 999999999u);
  EXPECT_EQ(ros_time(-1).sec, -1);
  EXPECT_EQ(ros_time(-1).nanosec, 999999999u);
}

}  // namespace
}  // namespace tofcomp::bridges::ros2
