#include "hal/lms2xx/scan_timing.hpp"

#include <cmath>

namespace tofcomp::hal::lms2xx {
namespace {

constexpr double kNanosecondsPerSecond = 1e9;

double turn_period_ns() {
  return kNanosecondsPerSecond / kMirrorTurnsPerSecond;
}

// Δ: consecutive rays of one turn are `turns × resolution` degrees apart.
double ray_interval_ns(const Variant& variant) {
  const double degrees_apart =
      variant.turns_per_scan() * static_cast<double>(variant.resolution_centideg) / 100.0;
  return turn_period_ns() * degrees_apart / kDegreesPerTurn;
}

std::chrono::nanoseconds rounded_ns(double ns) {
  return std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(ns)));
}

}  // namespace

std::chrono::nanoseconds line_transfer_time(std::size_t bytes, unsigned baud) {
  return rounded_ns(kBitsPerLineByte * static_cast<double>(bytes) * kNanosecondsPerSecond /
                    static_cast<double>(baud));
}

std::chrono::nanoseconds scan_sweep_duration(const Variant& variant) {
  const int turns = variant.turns_per_scan();
  const int beams = variant.values_per_scan();
  // The last beam the last turn (t = turns − 1) measures: the largest i < beams with
  // i mod turns = turns − 1, at position ⌊i / turns⌋ of its turn.
  const int last_beam = (beams - turns) / turns * turns + (turns - 1);
  return rounded_ns((turns - 1) * turn_period_ns() +
                    (last_beam / turns) * ray_interval_ns(variant));
}

core::RayTiming estimate_ray_timing(std::chrono::system_clock::time_point last_byte,
                                    std::size_t telegram_bytes, unsigned baud,
                                    const Variant& variant) {
  const auto first_ray =
      last_byte - line_transfer_time(telegram_bytes, baud) - scan_sweep_duration(variant);
  core::RayTiming timing;
  timing.first_ray_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(first_ray.time_since_epoch()).count();
  timing.ray_interval_ns = ray_interval_ns(variant);
  timing.turn_period_ns = turn_period_ns();
  timing.interlaced_turns = static_cast<std::uint32_t>(variant.turns_per_scan());
  return timing;
}

}  // namespace tofcomp::hal::lms2xx
