// The residual tests (core/residual_diagnosis.hpp, the evidence `tofcomp diagnose` prints beside
// its model search) on twin data: each effect scenario gets its effect named first, and data
// with no effect raise no finding in at least 95 % of seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "calibration/diagnosis.hpp"
#include "calibration/measured_data_reader.hpp"
#include "calibration/training.hpp"
#include "core/error.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/paper_structure_settings.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

// The paper's structure as §8 prints it (an order-4 polynomial, two modes, the LMS 200 filter
// levels), fixed rather than chosen from the data: these tests judge the residual tests and the
// extensions against Eq. 8 as printed. Chosen from the data, a flexible basis takes in what the
// twin's equal power cycles make a function of the temperature (the heating rate while ranging,
// the time since power-on) and a third mode takes in an extra mode, so that those effects are
// no longer beyond the model (docs/closing-the-loop.md). Likewise the junction's dynamics stay
// the thermal fit's: taken from the ranges (calibration/junction_dynamics.hpp), a slower junction
// takes in heating hysteresis (a junction that lags by τ more reads as a bias on the heating
// rate, t^j(t − τ) ≈ t^j − τ dt^j/dt).
TrainSettings datasheet_settings() {
  return test::paper_structure_settings();
}

core::Diagnosis diagnose_data(const MeasuredData& data) {
  return diagnose(data, train_calibration(data, datasheet_settings()).calibration);
}

core::Diagnosis diagnose_scenario(const std::string& name, std::uint64_t seed) {
  sim::Scenario scenario =
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/" + name + ".yaml");
  scenario.seed = seed;
  return diagnose_data(test::twin_measured_data(scenario));
}

struct Case {
  const char* scenario;
  core::EffectKind expected;
};

class DiagnoseNamesTheEffect : public ::testing::TestWithParam<Case> {};

TEST_P(DiagnoseNamesTheEffect, First) {
  const core::Diagnosis d = diagnose_scenario(GetParam().scenario, 7);
  ASSERT_FALSE(d.findings.empty());
  EXPECT_TRUE(d.findings.front().significant) << GetParam().scenario;
  EXPECT_EQ(d.findings.front().kind, GetParam().expected)
      << GetParam().scenario << " named " << core::effect_name(d.findings.front().kind);
}

INSTANTIATE_TEST_SUITE_P(
    Effects, DiagnoseNamesTheEffect,
    ::testing::Values(
        Case{"effect-mode-persistence", core::EffectKind::ModePersistence},
        Case{"effect-temperature-weights", core::EffectKind::TemperatureDependentWeights},
        Case{"effect-temperature-spread", core::EffectKind::TemperatureDependentSpread},
        Case{"effect-heating-hysteresis", core::EffectKind::HeatingHysteresis},
        Case{"effect-time-drift", core::EffectKind::TimeDrift},
        Case{"effect-warm-up", core::EffectKind::WarmUp},
        Case{"effect-outliers", core::EffectKind::Outliers},
        Case{"effect-extra-mode", core::EffectKind::ExtraMode}));

// Bonferroni at 5 % family-wise: over 20 data sets with no effect, at most 3 alarms
// (P(X ≥ 4) = 1.6 % for a binomial(20, 0.05)). Half the seeds play the default scenario, half
// the warm-up scenario's schedule of unequal pauses without its effect (where the warm-up test
// is not confounded with the temperature).
TEST(Diagnose, FalseAlarmsOnDataWithoutEffect) {
  int alarms = 0;
  for (std::uint64_t seed = 100; seed < 120; ++seed) {
    sim::Scenario scenario =
        sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/" +
                                (seed % 2 == 0 ? "default" : "effect-warm-up") + ".yaml");
    scenario.effects = {};
    scenario.seed = seed;
    const MeasuredData data = test::twin_measured_data(scenario);
    const core::Diagnosis d = diagnose_data(data);
    if (!d.findings.empty() && d.findings.front().significant) ++alarms;
  }
  EXPECT_LE(alarms, 3);
}

}  // namespace
}  // namespace tofcomp::calibration
