// The junction's dynamics completed from the ranges (calibration/junction_dynamics.hpp), on the
// twin, whose device is known:
//   - a device whose junction is hotter and slower than the datasheet's (P·R1 4.5 K against
//     1.8 K, R1·C1 36 s against 10.8 s), logged by a case sensor too coarse and noisy (0.25 °C
//     steps, 0.2 °C noise) for the case-log fit to see its junction, is found by training's
//     defaults: the ranges reject the case-log fit's junction, and the time constant lies at
//     most half as far from the device's as the datasheet's does (in logarithm). The rise is not
//     asserted: the junction visits the temperatures below its steady range only in the
//     transients after power-on, so the bias there is learned from those transients alone and
//     trades off against the rise (the prior keeps the rise near the datasheet's; 1.9 K here);
//   - a device whose junction is the datasheet's keeps the case-log fit's junction (the
//     ranges' t-test over blocks holds it);
//   - the parametrization keeps P, R2 and C2 and sets R1 and C1 from the two products.
#include <gtest/gtest.h>

#include <cmath>

#include "calibration/training.hpp"
#include "core/error.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

const std::string kRoot = TOFCOMP_SOURCE_ROOT;
constexpr double kCoarseSensorNoiseC = 0.2;
constexpr double kCoarseSensorResolutionC = 0.25;

// The default scenario (six hours, the paper's schedule), with its junction's products set and a
// coarse, noisy case sensor.
sim::Scenario scenario_with_junction(double rise_k, double time_constant_s) {
  sim::Scenario scenario = sim::load_scenario_file(kRoot + "/config/scenarios/default.yaml");
  scenario.thermal.r1_k_per_w = rise_k / scenario.thermal.power_w;
  scenario.thermal.c1_j_per_k = time_constant_s / scenario.thermal.r1_k_per_w;
  scenario.sensor.noise_std_c = kCoarseSensorNoiseC;
  scenario.sensor.resolution_c = kCoarseSensorResolutionC;
  return scenario;
}

double log_distance(double a, double b) { return std::abs(std::log(a / b)); }

Training train_with_defaults(const sim::Scenario& scenario) {
  TrainSettings settings;
  settings.thermal.datasheet = io::read_datasheet_file(kRoot + "/config/lms200-datasheet.yaml");
  return train_calibration(test::twin_measured_data(scenario), settings);
}

TEST(JunctionDynamics, ParametrizationKeepsTheCaseSide) {
  const core::ThermalParameters p{0.18, 0.5, 60.0, 2000.0, 10.0};
  const JunctionDynamics d = junction_dynamics_of(p);
  EXPECT_DOUBLE_EQ(d.rise_k, 1.8);
  EXPECT_DOUBLE_EQ(d.time_constant_s, 10.8);
  const core::ThermalParameters q = with_junction_dynamics(p, {4.5, 36.0});
  EXPECT_DOUBLE_EQ(q.power_w, p.power_w);
  EXPECT_DOUBLE_EQ(q.r2_k_per_w, p.r2_k_per_w);
  EXPECT_DOUBLE_EQ(q.c2_j_per_k, p.c2_j_per_k);
  EXPECT_NEAR(q.power_w * q.r1_k_per_w, 4.5, 1e-12);
  EXPECT_NEAR(q.r1_k_per_w * q.c1_j_per_k, 36.0, 1e-12);
}

TEST(JunctionDynamics, ADeviceUnlikeTheDatasheetIsFoundInItsRanges) {
  const JunctionDynamics device{4.5, 36.0};
  const Training t = train_with_defaults(scenario_with_junction(device.rise_k, device.time_constant_s));
  ASSERT_TRUE(t.junction_dynamics.has_value());
  const JunctionDynamicsFit& fit = *t.junction_dynamics;
  // The case-log fit does not see the device's junction here: what follows is the ranges' work.
  ASSERT_GT(log_distance(fit.start.dynamics.time_constant_s, device.time_constant_s),
            0.5 * log_distance(fit.datasheet.time_constant_s, device.time_constant_s));
  EXPECT_TRUE(fit.replaced) << "t " << fit.block_t << ", p " << fit.block_p;
  const JunctionDynamics found = junction_dynamics_of(t.calibration.thermal);
  EXPECT_LT(log_distance(found.time_constant_s, device.time_constant_s),
            0.5 * log_distance(fit.datasheet.time_constant_s, device.time_constant_s))
      << "time constant " << found.time_constant_s << " s";
  // The calibration carries what the ranges chose, and the case side is the case-log fit's.
  EXPECT_DOUBLE_EQ(t.calibration.thermal.power_w, t.thermal.identified().power_w);
  EXPECT_DOUBLE_EQ(t.calibration.thermal.r2_k_per_w, t.thermal.identified().r2_k_per_w);
  EXPECT_DOUBLE_EQ(t.calibration.thermal.c2_j_per_k, t.thermal.identified().c2_j_per_k);
  // The search evaluated points, and the best is the best of them.
  ASSERT_FALSE(fit.evaluated.empty());
  for (const JunctionDynamicsPoint& p : fit.evaluated) {
    EXPECT_LE(p.log_posterior(), fit.best.log_posterior() + 1e-9);
  }
}

TEST(JunctionDynamics, TheDatasheetsJunctionIsKept) {
  const Training t = train_with_defaults(scenario_with_junction(1.8, 10.8));
  ASSERT_TRUE(t.junction_dynamics.has_value());
  EXPECT_FALSE(t.junction_dynamics->replaced)
      << "t " << t.junction_dynamics->block_t << ", p " << t.junction_dynamics->block_p;
  EXPECT_DOUBLE_EQ(t.calibration.thermal.r1_k_per_w, t.thermal.identified().r1_k_per_w);
  EXPECT_DOUBLE_EQ(t.calibration.thermal.c1_j_per_k, t.thermal.identified().c1_j_per_k);
}

TEST(JunctionDynamics, OffLeavesTheThermalFit) {
  TrainSettings settings;
  settings.thermal.datasheet = io::read_datasheet_file(kRoot + "/config/lms200-datasheet.yaml");
  settings.junction_from_ranges = false;
  settings.basis = "polynomial:4";
  settings.modes = 2;
  const Training t =
      train_calibration(test::twin_measured_data(scenario_with_junction(4.5, 36.0)), settings);
  EXPECT_FALSE(t.junction_dynamics.has_value());
  EXPECT_DOUBLE_EQ(t.calibration.thermal.r1_k_per_w, t.thermal.identified().r1_k_per_w);
}

TEST(JunctionDynamics, OptionsAreChecked) {
  JunctionDynamicsOptions options;
  options.rejection_level = 0.0;
  EXPECT_THROW(options.validate(), core::InvalidInput);
  options = {};
  options.max_evaluations = 1;
  EXPECT_THROW(options.validate(), core::InvalidInput);
  options = {};
  options.initial_log_step = 0.0;
  EXPECT_THROW(options.validate(), core::InvalidInput);
}

}  // namespace
}  // namespace tofcomp::calibration
