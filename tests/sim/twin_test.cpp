#include "sim/twin.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.hpp"
#include "io/yaml_fields.hpp"
#include "sim/scenario_yaml.hpp"

namespace tofcomp::sim {
namespace {

Scenario bench_scenario() {
  Scenario s;
  s.seed = 7;
  s.thermal = {0.2, 0.5, 60.0, 2000.0, 10.0};
  s.power = {{true, 3000.0}, {false, 600.0}, {true, 1200.0}};
  s.modes = {{-2.0, 0.9, 0.6}, {2.5, 1.1, 0.4}};
  s.range_period_s = 0.5;
  return s;
}

// After many time constants on, the twin rests at Eq. 3's equilibrium: t^c = t^a + P R2,
// t^j = t^c + P R1.
TEST(Twin, ReachesTheThermalEquilibrium) {
  Scenario s = bench_scenario();
  s.power = {{true, 20000.0}};
  Twin twin(s);
  twin.advance_to(19999.0);
  EXPECT_NEAR(twin.case_c(), 22.0 + 10.0 * 0.5, 1e-3);
  EXPECT_NEAR(twin.junction_c(), 22.0 + 10.0 * 0.7, 1e-3);
}

// Cooling from the equilibrium follows the slow pole: with the power off, after one time
// constant of the case the excess is e^{-1} of the start to within the fast pole's share.
TEST(Twin, CoolsTowardAmbient) {
  Scenario s = bench_scenario();
  s.power = {{false, 50000.0}};
  s.initial_case_c = 30.0;
  Twin twin(s);
  twin.advance_to(40000.0);
  EXPECT_NEAR(twin.case_c(), 22.0, 1e-6);
  EXPECT_NEAR(twin.junction_c(), 22.0, 1e-6);
}

TEST(Twin, SeriesFollowsTheScheduleAndQuantizes) {
  const Scenario s = bench_scenario();
  const TwinSeries series = simulate_series(s);
  // Ranges every 0.5 s during the 4200 s the power is on.
  EXPECT_EQ(series.ranges.size(), 8400u);
  ASSERT_EQ(series.power_changes.size(), 3u);
  EXPECT_TRUE(series.power_changes[0].on);
  EXPECT_DOUBLE_EQ(series.power_changes[1].time_s, 3000.0);
  EXPECT_FALSE(series.power_changes[1].on);
  EXPECT_DOUBLE_EQ(series.power_changes[2].time_s, 3600.0);
  EXPECT_EQ(series.temperatures.size(), 4800u);
  for (const auto& r : series.ranges) {
    ASSERT_EQ(r.range_mm, std::round(r.range_mm));
    ASSERT_FALSE(r.time_s >= 3000.0 && r.time_s < 3600.0) << "range while off at " << r.time_s;
  }
  for (const auto& t : series.temperatures) {
    ASSERT_DOUBLE_EQ(t.case_c / 0.0625, std::round(t.case_c / 0.0625));
  }
}

// The residual y − d − bias − μ_mode is the mode's Gaussian plus the 1 mm rounding (variance
// σ² + 1/12), and each mode fires with its weight.
TEST(Twin, RangesFollowEquation8) {
  const Scenario s = bench_scenario();
  const TwinSeries series = simulate_series(s);
  double count[2] = {0, 0}, sum[2] = {0, 0}, sum2[2] = {0, 0};
  for (const auto& r : series.ranges) {
    const double e = r.range_mm - r.true_range_mm - r.bias_mm - s.modes[r.mode].offset_mm;
    count[r.mode] += 1;
    sum[r.mode] += e;
    sum2[r.mode] += e * e;
  }
  const double n = static_cast<double>(series.ranges.size());
  EXPECT_NEAR(count[0] / n, 0.6, 4 * std::sqrt(0.24 / n));
  for (int m = 0; m < 2; ++m) {
    const double mean = sum[m] / count[m];
    const double var = sum2[m] / count[m] - mean * mean;
    const double expected_var = s.modes[m].std_mm * s.modes[m].std_mm + 1.0 / 12.0;
    EXPECT_NEAR(mean, 0.0, 0.05) << m;
    EXPECT_NEAR(var / expected_var, 1.0, 0.08) << m;
  }
}

TEST(Twin, CentimetreModeRoundsToTenMillimetres) {
  Scenario s = bench_scenario();
  s.scanner.units = RangeUnits::Centimetre;
  for (const auto& r : simulate_series(s).ranges) {
    ASSERT_DOUBLE_EQ(r.range_mm / 10.0, std::round(r.range_mm / 10.0));
  }
}

TEST(Twin, BeyondTheRangeLimitIsNoEcho) {
  Scenario s = bench_scenario();
  s.true_range_mm = 9000.0;
  const TwinSeries series = simulate_series(s);
  EXPECT_TRUE(series.ranges.empty());
  EXPECT_EQ(series.no_echo_count, 8400);
}

TEST(Twin, SeededAndReproducible) {
  const TwinSeries a = simulate_series(bench_scenario());
  const TwinSeries b = simulate_series(bench_scenario());
  Scenario other = bench_scenario();
  other.seed = 8;
  const TwinSeries c = simulate_series(other);
  ASSERT_EQ(a.ranges.size(), b.ranges.size());
  int differ = 0;
  for (std::size_t i = 0; i < a.ranges.size(); ++i) {
    ASSERT_EQ(a.ranges[i].range_mm, b.ranges[i].range_mm);
    differ += a.ranges[i].range_mm != c.ranges[i].range_mm;
  }
  EXPECT_GT(differ, 1000);
}

// A host's power switch overrides the schedule: off, the laser's heat input is 0 (u of Eq. 4)
// and the twin cools exactly as with the power off in its schedule; on again, it heats as a
// schedule that is on. Released, the schedule decides again.
TEST(Twin, PowerOverrideSetsTheHeatInputWhateverTheSchedule) {
  Scenario on_schedule = bench_scenario();
  on_schedule.power = {{true, 50000.0}};
  Scenario off_schedule = bench_scenario();
  off_schedule.power = {{true, 1000.0}, {false, 49000.0}};
  Twin switched(on_schedule);
  Twin scheduled(off_schedule);
  switched.advance_to(1000.0);
  scheduled.advance_to(1000.0);
  switched.set_power_override(false);
  EXPECT_FALSE(switched.power_on());
  switched.advance_to(2500.0);
  scheduled.advance_to(2500.0);
  EXPECT_DOUBLE_EQ(switched.case_c(), scheduled.case_c());
  EXPECT_DOUBLE_EQ(switched.junction_c(), scheduled.junction_c());
  EXPECT_LT(switched.junction_c(), 22.0 + 10.0 * 0.7 - 1.0);  // cooled from the heated state

  Twin heated(off_schedule);
  heated.set_power_override(true);
  heated.advance_to(40000.0);  // the schedule says off from 1000 s: the override keeps it on
  EXPECT_TRUE(heated.power_on());
  EXPECT_NEAR(heated.junction_c(), 22.0 + 10.0 * 0.7, 1e-3);
  heated.set_power_override(std::nullopt);
  EXPECT_FALSE(heated.power_on());
}

TEST(Twin, RejectsSteppingBack) {
  Twin twin(bench_scenario());
  twin.advance_to(10.0);
  EXPECT_THROW(twin.advance_to(5.0), core::InvalidInput);
}

TEST(ScenarioYaml, DefaultScenarioResemblesThePaper) {
  const Scenario s =
      load_scenario_file(std::string(TOFCOMP_SOURCE_ROOT) + "/config/scenarios/default.yaml");
  const TwinSeries series = simulate_series(s);
  EXPECT_NEAR(static_cast<double>(series.ranges.size()), 20000.0, 10.0);
  double lo = 1e9, hi = -1e9;
  for (const auto& r : series.ranges) {
    lo = std::min(lo, r.junction_c);
    hi = std::max(hi, r.junction_c);
  }
  EXPECT_NEAR(lo, 24.8, 0.3);
  EXPECT_NEAR(hi, 28.8, 0.3);
}

std::string write_temp(const std::string& text) {
  const std::string path = ::testing::TempDir() + "/scenario_test.yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(ScenarioYaml, ErrorsNameTheKey) {
  const std::string base =
      "thermal: {r1_k_per_w: 0.2, r2_k_per_w: 0.5, c1_j_per_k: 60, c2_j_per_k: 2000, "
      "power_w: 10}\npower: {segments: [{on: true, duration_s: 100}]}\n";
  const std::string modes = "modes: [{offset_mm: 0, std_mm: 1, weight: 1}]\n";
  EXPECT_NO_THROW(load_scenario_file(write_temp(base + modes)));
  auto message = [&](const std::string& text) {
    try {
      load_scenario_file(write_temp(text));
    } catch (const io::YamlSchemaError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(base + modes + "colour: red\n").find("colour is not a known key"),
            std::string::npos);
  EXPECT_NE(message(base).find("modes is missing"), std::string::npos);
  EXPECT_NE(
      message(base + "modes: [{offset_mm: 0, std_mm: -1, weight: 1}]\n").find("modes[0].std_mm"),
      std::string::npos);
  EXPECT_NE(message(base + modes + "true_range_mm: far\n").find("true_range_mm must be a finite"),
            std::string::npos);
  EXPECT_NE(message("thermal: [1, 2\n").find("YAML syntax error"), std::string::npos);
}

}  // namespace
}  // namespace tofcomp::sim
