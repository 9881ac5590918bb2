// The LMS 2xx's ray timing from public device facts (75 mirror turns a second, interlaced turns at
// 0.5° and 0.25°, 10 line bits a byte), against durations worked out by hand.
#include "hal/lms2xx/scan_timing.hpp"

#include <gtest/gtest.h>

namespace tofcomp::hal::lms2xx {
namespace {

constexpr double kTurnMs = 1000.0 / 75.0;  // 13.333 ms

double ms(std::chrono::nanoseconds d) {
  return static_cast<double>(d.count()) / 1e6;
}

TEST(ScanTiming, LineTransferTimeIsTenBitsAByte) {
  // A 361-value scan telegram: 7 bytes of frame, 2 + 722 of data and the status byte.
  EXPECT_NEAR(ms(line_transfer_time(732, 500000)), 14.64, 1e-6);
  EXPECT_NEAR(ms(line_transfer_time(732, 38400)), 190.625, 1e-6);
  EXPECT_NEAR(ms(line_transfer_time(1, 9600)), 1.0416667, 1e-6);
}

TEST(ScanTiming, SweepRunsFromBeamZeroToTheLastTurnsLastBeam) {
  // 1°, 180°: one turn, the last of 181 rays 180° after the first.
  EXPECT_NEAR(ms(scan_sweep_duration({180, 100})), kTurnMs * 180.0 / 360.0, 1e-5);
  // 0.5°, 180°: two turns at 1° steps; the second turn measures the odd beams, its last is beam
  // 359 (179.5°), 179 rays after that turn's first.
  EXPECT_NEAR(ms(scan_sweep_duration({180, 50})), kTurnMs + kTurnMs * 179.0 / 360.0, 1e-5);
  // 0.5°, 100°: 201 beams; the second turn's last is beam 199, 99 rays on.
  EXPECT_NEAR(ms(scan_sweep_duration({100, 50})), kTurnMs + kTurnMs * 99.0 / 360.0, 1e-5);
  // 0.25°, 100°: four turns at 1° steps; the fourth measures beams 3, 7, ..., 399 (99 rays on).
  EXPECT_NEAR(ms(scan_sweep_duration({100, 25})), 3 * kTurnMs + kTurnMs * 99.0 / 360.0, 1e-5);
}

TEST(ScanTiming, FirstRayIsTheArrivalLessLineTimeAndSweep) {
  const auto arrival = std::chrono::system_clock::time_point(std::chrono::seconds(1'700'000'000));
  const core::RayTiming rays = estimate_ray_timing(arrival, 732, 500000, {180, 50});
  constexpr std::int64_t kArrivalNs = 1'700'000'000'000'000'000;
  const double expected_ms = 14.64 + kTurnMs + kTurnMs * 179.0 / 360.0;
  EXPECT_NEAR(static_cast<double>(kArrivalNs - rays.first_ray_ns) / 1e6, expected_ms, 1e-5);
  EXPECT_EQ(rays.interlaced_turns, 2u);
  EXPECT_NEAR(rays.turn_period_ns, kTurnMs * 1e6, 1e-3);
  // Consecutive rays of one turn are 1° apart.
  EXPECT_NEAR(rays.ray_interval_ns, kTurnMs * 1e6 / 360.0, 1e-3);
  // Beam 1 is the second turn's first ray; beam 2 the first turn's second; beam 359 the last.
  EXPECT_NEAR(rays.beam_offset_ns(1), kTurnMs * 1e6, 1e-3);
  EXPECT_NEAR(rays.beam_offset_ns(2), kTurnMs * 1e6 / 360.0, 1e-3);
  EXPECT_NEAR(rays.beam_offset_ns(359) / 1e6, ms(scan_sweep_duration({180, 50})), 1e-5);
}

TEST(ScanTiming, UnknownTimingHasNoOffsets) {
  const core::RayTiming unknown;
  EXPECT_FALSE(unknown.known());
  EXPECT_EQ(unknown.beam_offset_ns(100), 0.0);
}

}  // namespace
}  // namespace tofcomp::hal::lms2xx
