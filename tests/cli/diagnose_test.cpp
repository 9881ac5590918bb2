// The residual diagnosis on twin data: each effect scenario gets its effect named first, and
// data with no effect raise no finding in at least 95 % of seeds.
#include <gtest/gtest.h>

#include "cli/covariate_extension.hpp"
#include "cli/measured_data_csv.hpp"
#include "cli/pipeline.hpp"
#include "core/error.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"

namespace tofcomp::cli {
namespace {

const std::string kRoot = TOFCOMP_SOURCE_ROOT;

core::Diagnosis diagnose_scenario(const std::string& name, std::uint64_t seed) {
  sim::Scenario scenario = sim::load_scenario_file(kRoot + "/config/scenarios/" + name + ".yaml");
  scenario.seed = seed;
  const std::string file = ::testing::TempDir() + "/" + name + ".csv";
  write_twin_series(file, scenario, sim::simulate_series(scenario));
  std::vector<std::string> warnings;
  const MeasuredData data = read_measured_data(file, 0, warnings);
  TrainSettings settings;
  settings.thermal.datasheet = io::read_datasheet_file(kRoot + "/config/lms200-datasheet.yaml");
  return diagnose(data, train_calibration(data, settings).calibration);
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
        Case{"effect-time-drift", core::EffectKind::TimeDrift}));

// Bonferroni at 5 % family-wise: over 20 seeds of the default scenario, at most 3 alarms
// (P(X ≥ 4) = 1.6 % for a binomial(20, 0.05)).
TEST(Diagnose, FalseAlarmsOnDataWithoutEffect) {
  int alarms = 0;
  for (std::uint64_t seed = 100; seed < 120; ++seed) {
    const core::Diagnosis d = diagnose_scenario("default", seed);
    alarms += !d.findings.empty() && d.findings.front().significant;
  }
  EXPECT_LE(alarms, 3);
}

}  // namespace
}  // namespace tofcomp::cli

namespace tofcomp::cli {
namespace {

MeasuredData twin_data(const std::string& name) {
  const sim::Scenario scenario =
      sim::load_scenario_file(kRoot + "/config/scenarios/" + name + ".yaml");
  const std::string file = ::testing::TempDir() + "/ext_" + name + ".csv";
  write_twin_series(file, scenario, sim::simulate_series(scenario));
  std::vector<std::string> warnings;
  return read_measured_data(file, 0, warnings);
}

// The covariate extensions recover the twin's coefficient and are kept by held-out data.
TEST(CovariateExtension, RecoversTheEffectAndIsKept) {
  TrainSettings settings;
  settings.thermal.datasheet = io::read_datasheet_file(kRoot + "/config/lms200-datasheet.yaml");
  struct Expect {
    const char* scenario;
    core::EffectKind effect;
    double coefficient;  // the scenario's parameter
    double min_factor;   // held-out MAE before / after
  };
  for (const Expect& e :
       {Expect{"effect-time-drift", core::EffectKind::TimeDrift, 0.5, 3.0},
        Expect{"effect-heating-hysteresis", core::EffectKind::HeatingHysteresis, 2.0, 1.2}}) {
    const MeasuredData data = twin_data(e.scenario);
    const double split = split_time(data, 0.5);
    const ExtensionReport r = evaluate_covariate_extension(
        e.effect, data.slice(-1e300, split), data.slice(split, 1e300), settings, 400, 20);
    EXPECT_NEAR(r.coefficient, e.coefficient, 0.2 * e.coefficient) << e.scenario;
    EXPECT_TRUE(r.kept) << e.scenario;
    EXPECT_GT(r.before.mean_absolute_error / r.after.mean_absolute_error, e.min_factor)
        << e.scenario;
  }
  EXPECT_THROW(evaluate_covariate_extension(core::EffectKind::Outliers, twin_data("default"),
                                            twin_data("default"), settings, 400, 20),
               core::InvalidInput);
}

}  // namespace
}  // namespace tofcomp::cli
