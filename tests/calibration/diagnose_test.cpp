// The residual diagnosis on twin data: each effect scenario gets its effect named first, and
// data with no effect raise no finding in at least 95 % of seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "calibration/diagnosis.hpp"
#include "calibration/measured_data_reader.hpp"
#include "calibration/model_extension.hpp"
#include "calibration/training.hpp"
#include "core/error.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "sim/twin_csv.hpp"

namespace tofcomp::calibration {
namespace {

const std::string kRoot = TOFCOMP_SOURCE_ROOT;

MeasuredData scenario_data(const sim::Scenario& scenario) {
  const std::string file = ::testing::TempDir() + "/" + scenario.name + ".csv";
  sim::write_twin_measured_data(file, scenario, sim::simulate_series(scenario));
  std::vector<std::string> warnings;
  return read_measured_data(file, 0, warnings);
}

// The paper's structure as §8 prints it (an order-4 polynomial, two modes, the LMS 200 filter
// levels), fixed rather than chosen from the data: these tests judge the residual tests and the
// extensions against Eq. 8 as printed. Chosen from the data, a flexible basis takes in what the
// twin's equal power cycles make a function of the temperature (the heating rate while ranging,
// the time since power-on) and a third mode takes in an extra mode, so that those effects are
// no longer beyond the model (docs/closing-the-loop.md).
TrainSettings datasheet_settings() {
  TrainSettings settings;
  settings.thermal.datasheet = io::read_datasheet_file(kRoot + "/config/lms200-datasheet.yaml");
  settings.basis = "polynomial:4";
  settings.modes = 2;
  settings.kalman_noise = core::ThermalNoise{};
  return settings;
}

core::Diagnosis diagnose_data(const MeasuredData& data) {
  return diagnose(data, train_calibration(data, datasheet_settings()).calibration);
}

core::Diagnosis diagnose_scenario(const std::string& name, std::uint64_t seed) {
  sim::Scenario scenario = sim::load_scenario_file(kRoot + "/config/scenarios/" + name + ".yaml");
  scenario.seed = seed;
  return diagnose_data(scenario_data(scenario));
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
// (P(X ≥ 4) = 1.6 % for a binomial(20, 0.05)). An extension is fitted only after an alarm and
// kept only on held-out gain: the same bound holds for the extensions kept. Half the seeds play
// the default scenario, half the warm-up scenario's schedule of unequal pauses without its
// effect (where the warm-up test is not confounded with the temperature).
TEST(Diagnose, FalseAlarmsOnDataWithoutEffect) {
  const TrainSettings settings = datasheet_settings();
  int alarms = 0;
  int kept = 0;
  for (std::uint64_t seed = 100; seed < 120; ++seed) {
    sim::Scenario scenario = sim::load_scenario_file(
        kRoot + "/config/scenarios/" + (seed % 2 == 0 ? "default" : "effect-warm-up") + ".yaml");
    scenario.effects = {};
    scenario.seed = seed;
    const MeasuredData data = scenario_data(scenario);
    const core::Diagnosis d = diagnose_data(data);
    if (d.findings.empty() || !d.findings.front().significant) continue;
    ++alarms;
    const double split = split_time(data, 0.5);
    kept += evaluate_extension(d.findings.front().kind, data.slice(-1e300, split),
                               data.slice(split, 1e300), settings, {400}, 20)
                .kept;
  }
  EXPECT_LE(alarms, 3);
  EXPECT_LE(kept, 3);
}

}  // namespace
}  // namespace tofcomp::calibration

namespace tofcomp::calibration {
namespace {

MeasuredData twin_data(const std::string& name) {
  const sim::Scenario scenario =
      sim::load_scenario_file(kRoot + "/config/scenarios/" + name + ".yaml");
  const std::string file = ::testing::TempDir() + "/ext_" + name + ".csv";
  sim::write_twin_measured_data(file, scenario, sim::simulate_series(scenario));
  std::vector<std::string> warnings;
  return read_measured_data(file, 0, warnings);
}

struct ExtensionCase {
  const char* scenario;
  core::EffectKind effect;
  double min_factor;  // held-out MAE of d̂, the paper's model / the extension, at least
};

class ExtensionCutsTheError : public ::testing::TestWithParam<ExtensionCase> {};

// Each extension, fitted on the first half of a scenario carrying its effect, raises the
// held-out likelihood, is kept, and cuts the held-out MAE of d̂ by at least the factor given
// (each a margin below what seed 20151211 gives: docs/closing-the-loop.md).
TEST_P(ExtensionCutsTheError, OnHeldOutData) {
  const TrainSettings settings = datasheet_settings();
  const MeasuredData data = twin_data(GetParam().scenario);
  const double split = split_time(data, 0.5);
  const ExtensionReport r =
      evaluate_extension(GetParam().effect, data.slice(-1e300, split), data.slice(split, 1e300),
                         settings, {200, 400, 800}, 20);
  EXPECT_EQ(r.effect, GetParam().effect);
  EXPECT_GT(r.held_out_log_likelihood_gain(), 0.0);
  EXPECT_TRUE(r.kept) << GetParam().scenario;
  EXPECT_GT(r.mean_absolute_error_factor(), GetParam().min_factor) << GetParam().scenario;
  ASSERT_TRUE(r.calibration.extension.has_value());
  EXPECT_EQ(r.calibration.extension->effect, GetParam().effect);
}

INSTANTIATE_TEST_SUITE_P(
    Effects, ExtensionCutsTheError,
    ::testing::Values(
        ExtensionCase{"effect-time-drift", core::EffectKind::TimeDrift, 3.0},
        ExtensionCase{"effect-heating-hysteresis", core::EffectKind::HeatingHysteresis, 1.2},
        ExtensionCase{"effect-warm-up", core::EffectKind::WarmUp, 2.2},
        ExtensionCase{"effect-outliers", core::EffectKind::Outliers, 1.6},
        ExtensionCase{"effect-mode-persistence", core::EffectKind::ModePersistence, 1.1},
        ExtensionCase{"effect-extra-mode", core::EffectKind::ExtraMode, 1.05}));

// The covariate extensions recover the twin's coefficient.
TEST(ModelExtension, RecoversTheCovariateCoefficient) {
  const TrainSettings settings = datasheet_settings();
  for (const auto& [scenario, effect, coefficient] :
       {std::tuple{"effect-time-drift", core::EffectKind::TimeDrift, 0.5},
        std::tuple{"effect-heating-hysteresis", core::EffectKind::HeatingHysteresis, 2.0},
        std::tuple{"effect-warm-up", core::EffectKind::WarmUp, 3.0}}) {
    const MeasuredData data = twin_data(scenario);
    const double split = split_time(data, 0.5);
    const ExtensionReport r = evaluate_extension(effect, data.slice(-1e300, split),
                                                 data.slice(split, 1e300), settings, {400}, 20);
    ASSERT_TRUE(r.calibration.extension.has_value());
    EXPECT_NEAR(r.calibration.extension->covariate_mm, coefficient, 0.2 * coefficient) << scenario;
    if (effect == core::EffectKind::WarmUp) {
      EXPECT_NEAR(r.calibration.extension->time_constant_s, 300.0, 60.0);  // the twin's τ
    }
  }
}

// The outlier component recovers the twin's outlier fraction and its two lasing modes.
TEST(ModelExtension, OutlierComponentRecoversTheModes) {
  const TrainSettings settings = datasheet_settings();
  const MeasuredData data = twin_data("effect-outliers");
  const double split = split_time(data, 0.5);
  const ExtensionReport r =
      evaluate_extension(core::EffectKind::Outliers, data.slice(-1e300, split),
                         data.slice(split, 1e300), settings, {400}, 20);
  ASSERT_TRUE(r.calibration.extension.has_value());
  const core::ExtendedMixture& n = r.calibration.extension->extended_mixture;
  // The scenario: 2 % outliers uniform in ±100 mm (a share within the modes' reach is taken for
  // inliers), modes 4.5 mm apart with σ 0.9 and 1.1 mm.
  EXPECT_NEAR(n.outlier_weight, 0.02, 0.006);
  ASSERT_EQ(n.modes.modes(), 2);
  EXPECT_NEAR(n.modes.mean[1] - n.modes.mean[0], 4.5, 0.3);
  EXPECT_NEAR(std::sqrt(n.modes.variance[0]), 0.9, 0.15);
  EXPECT_NEAR(std::sqrt(n.modes.variance[1]), 1.1, 0.15);
}

}  // namespace
}  // namespace tofcomp::calibration
