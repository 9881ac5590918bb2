// Each optional effect of the twin (sim/effects.hpp) does what docs/scenarios.md says, checked
// against an answer derived from the effect's definition.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sim/scenario_yaml.hpp"
#include "sim/twin.hpp"

namespace tofcomp::sim {
namespace {

const std::string kScenarios = std::string(TOFCOMP_SOURCE_ROOT) + "/config/scenarios/";

Scenario with(const std::string& file) {
  return load_scenario_file(kScenarios + file);
}

TEST(TwinEffects, EffectScenariosInheritTheDefault) {
  const Scenario base = with("default.yaml");
  const Scenario fx = with("effect-outliers.yaml");
  EXPECT_EQ(fx.name, "effect-outliers");
  EXPECT_EQ(fx.thermal.c2_j_per_k, base.thermal.c2_j_per_k);
  EXPECT_EQ(fx.modes.size(), base.modes.size());
  EXPECT_FALSE(base.effects.any());
  ASSERT_TRUE(fx.effects.outliers.has_value());
  EXPECT_DOUBLE_EQ(fx.effects.outliers->fraction, 0.02);
}

// A Markov chain that stays with probability s and otherwise redraws from π repeats the
// previous mode with probability s + (1 − s) Σ π_i².
TEST(TwinEffects, ModePersistenceRepeatsModes) {
  const Scenario s = with("effect-mode-persistence.yaml");
  const TwinSeries series = simulate_series(s);
  double repeats = 0;
  for (std::size_t i = 1; i < series.ranges.size(); ++i) {
    repeats += series.ranges[i].mode == series.ranges[i - 1].mode;
  }
  const double stay = s.effects.mode_persistence->stay_probability;
  const double expected = stay + (1 - stay) * (0.55 * 0.55 + 0.45 * 0.45);
  EXPECT_NEAR(repeats / static_cast<double>(series.ranges.size() - 1), expected, 0.01);
}

TEST(TwinEffects, OutliersAtTheirFraction) {
  const TwinSeries series = simulate_series(with("effect-outliers.yaml"));
  double outliers = 0;
  for (const auto& r : series.ranges) outliers += r.mode == -1;
  EXPECT_NEAR(outliers / static_cast<double>(series.ranges.size()), 0.02, 0.003);
}

TEST(TwinEffects, TimeDriftAddsToTheBias) {
  const Scenario s = with("effect-time-drift.yaml");
  for (const auto& r : simulate_series(s).ranges) {
    ASSERT_NEAR(r.bias_mm - s.bias.at(r.junction_c), 0.5 * r.time_s / 3600.0, 1e-9);
  }
}

// The warm-up scenario's schedule: on 1 h, off 5 min, on 1 h, off 40 min, on 1 h, off 20 min,
// twice. The transient is amplitude·exp(−t_on/τ) from each switch-on, which the series knows
// only through the schedule: computed here from it.
TEST(TwinEffects, WarmUpDecaysFromEachPowerOn) {
  const Scenario s = with("effect-warm-up.yaml");
  const double pauses[] = {300.0, 2400.0, 1200.0};
  std::vector<double> switch_on{0.0};
  for (int i = 0; i < 5; ++i) switch_on.push_back(switch_on.back() + 3600.0 + pauses[i % 3]);
  for (const auto& r : simulate_series(s).ranges) {
    double last_on = 0.0;
    for (const double t : switch_on) last_on = t <= r.time_s ? t : last_on;
    ASSERT_NEAR(r.bias_mm - s.bias.at(r.junction_c), 3.0 * std::exp(-(r.time_s - last_on) / 300.0),
                1e-9)
        << "at " << r.time_s << " s";
  }
}

// The twin's clock of the warm-up follows a power override as it follows the schedule.
TEST(TwinEffects, TimeSincePowerOnFollowsTheOverride) {
  Twin twin(with("default.yaml"));
  twin.advance_to(100.0);
  EXPECT_DOUBLE_EQ(twin.time_since_power_on_s(), 100.0);
  twin.set_power_override(false);
  twin.advance_to(200.0);
  EXPECT_DOUBLE_EQ(twin.time_since_power_on_s(), 0.0);
  twin.set_power_override(true);
  twin.advance_to(230.0);
  EXPECT_DOUBLE_EQ(twin.time_since_power_on_s(), 30.0);
}

// Heating (just after a power-on) adds to the bias; the extra term is k·60·dt^j/dt ≥ 0 while on.
TEST(TwinEffects, HeatingHysteresisFollowsTheHeatingRate) {
  const Scenario s = with("effect-heating-hysteresis.yaml");
  double early = 0, late = 0;
  int n_early = 0, n_late = 0;
  for (const auto& r : simulate_series(s).ranges) {
    const double extra = r.bias_mm - s.bias.at(r.junction_c);
    const double since_on = std::fmod(r.time_s, 3600.0 + 560.0);
    if (since_on < 60.0) {
      early += extra;
      ++n_early;
    } else if (since_on > 3000.0) {
      late += extra;
      ++n_late;
    }
  }
  EXPECT_GT(early / n_early, 0.3);          // the junction heats fast after switch-on
  EXPECT_LT(std::abs(late / n_late), 0.1);  // and hardly at the end of an hour on
}

TEST(TwinEffects, TemperatureDependentWeightsShiftTheModes) {
  const TwinSeries series = simulate_series(with("effect-temperature-weights.yaml"));
  double warm = 0, warm_n = 0, cool = 0, cool_n = 0;
  for (const auto& r : series.ranges) {
    if (r.junction_c > 28.0) {
      warm += r.mode == 1;
      ++warm_n;
    } else if (r.junction_c < 25.6) {
      cool += r.mode == 1;
      ++cool_n;
    }
  }
  EXPECT_GT(warm / warm_n, cool / cool_n + 0.3);
}

TEST(TwinEffects, TemperatureDependentSpreadWidensWhenWarm) {
  const Scenario s = with("effect-temperature-spread.yaml");
  double warm2 = 0, warm_n = 0, cool2 = 0, cool_n = 0;
  for (const auto& r : simulate_series(s).ranges) {
    const double e = r.range_mm - r.true_range_mm - r.bias_mm - s.modes[r.mode].offset_mm;
    if (r.junction_c > 28.0) {
      warm2 += e * e;
      ++warm_n;
    } else if (r.junction_c < 25.6) {
      cool2 += e * e;
      ++cool_n;
    }
  }
  EXPECT_GT(std::sqrt(warm2 / warm_n), 1.5 * std::sqrt(cool2 / cool_n));
}

// A 181-beam scan over 180° of a wall 3 m away: the centre beam sees 3 m, the beam 30° off
// sees 3 m / cos 30°, the beams along the wall see nothing within range.
TEST(TwinScan, WallGeometry) {
  Scenario s = with("default.yaml");
  s.scanner.beams = 181;
  s.modes = {{0.0, 1e-6, 1.0}};
  s.bias = {26.8, 0.0, 0.0, 0.0, 0.8};
  Twin twin(s);
  const auto scan = twin.scan();
  ASSERT_EQ(scan.size(), 181u);
  EXPECT_NEAR(scan[90].range_mm, 3000.0, 0.5);
  EXPECT_NEAR(scan[60].range_mm, 3000.0 / std::cos(std::numbers::pi / 6), 0.5);
  EXPECT_EQ(scan[0].status, ReadingStatus::NoEcho);
  EXPECT_EQ(scan[180].status, ReadingStatus::NoEcho);
}

// A scanning scenario records every beam of every scan, at the scan times.
TEST(TwinScan, SeriesRecordsEveryBeam) {
  Scenario s = with("default.yaml");
  s.scanner.beams = 181;
  s.scanner.field_deg = 100.0;
  s.power = {{true, 2.0}};
  s.range_period_s = 1.0 / 75.0;
  const TwinSeries series = simulate_series(s);
  ASSERT_EQ(series.ranges.size(), 150u * 181u);  // 75 scans/s for 2 s, all beams in range
  EXPECT_EQ(series.ranges[181].beam, 0);
  EXPECT_NEAR(series.ranges[181].time_s, 1.0 / 75.0, 1e-12);
  EXPECT_EQ(series.ranges[180].beam, 180);
}

}  // namespace
}  // namespace tofcomp::sim
