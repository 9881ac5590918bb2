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

#include "calibration/measured_data.hpp"
#include "calibration/training.hpp"
#include "core/error.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

constexpr double kCoarseSensorNoiseC = 0.2;
constexpr double kCoarseSensorResolutionC = 0.25;

// The default scenario (six hours, the paper's schedule), with its junction's products set and a
// coarse, noisy case sensor.
sim::Scenario scenario_with_junction(double rise_k, double time_constant_s) {
  sim::Scenario scenario =
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/default.yaml");
  scenario.thermal.r1_k_per_w = rise_k / scenario.thermal.power_w;
  scenario.thermal.c1_j_per_k = time_constant_s / scenario.thermal.r1_k_per_w;
  scenario.sensor.noise_std_c = kCoarseSensorNoiseC;
  scenario.sensor.resolution_c = kCoarseSensorResolutionC;
  return scenario;
}

double log_distance(double a, double b) {
  return std::abs(std::log(a / b));
}

Training train_with_defaults(const sim::Scenario& scenario) {
  TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
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
  const Training t =
      train_with_defaults(scenario_with_junction(device.rise_k, device.time_constant_s));
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
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  settings.junction_source = JunctionSource::CaseLog;
  settings.basis = "polynomial:4";
  settings.modes = 2;
  const Training t =
      train_calibration(test::twin_measured_data(scenario_with_junction(4.5, 36.0)), settings);
  EXPECT_FALSE(t.junction_dynamics.has_value());
  EXPECT_DOUBLE_EQ(t.calibration.thermal.r1_k_per_w, t.thermal.identified().r1_k_per_w);
}

// The junction dynamics' problem as training poses it, on the twin's datasheet device, with the
// filter's junction process noise q_j set by the test: `case_log_q_j` as if the case log had
// fitted it, `start_q_j` where that fit started.
struct JunctionNoiseCase {
  MeasuredData data;
  Training trained;
  TrainSettings settings;
};

JunctionNoiseCase datasheet_device() {
  JunctionNoiseCase c{test::twin_measured_data(scenario_with_junction(1.8, 10.8)), {}, {}};
  c.settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  c.trained = train_calibration(c.data, c.settings);
  return c;
}

JunctionDynamicsFit judge_junction_noise(const JunctionNoiseCase& c, double case_log_q_j,
                                         double start_q_j) {
  core::ThermalNoise case_log = c.trained.calibration.kalman_noise;
  case_log.junction_process_psd_k2_per_s = case_log_q_j;
  core::ThermalNoise held = case_log;
  held.junction_process_psd_k2_per_s = start_q_j;
  JunctionDynamicsOptions options;
  options.em = c.settings.search.em;
  options.em.variance_floor = kRangeResolutionMm * kRangeResolutionMm / 12.0;
  const JunctionDynamicsProblem problem{c.data,
                                        *c.trained.thermal.map,
                                        c.settings.thermal.prior,
                                        case_log,
                                        held,
                                        c.settings.thermal.ambient_fallback_c,
                                        c.trained.calibration.model.basis,
                                        c.trained.em.mixture.modes(),
                                        {c.trained.em.theta, c.trained.em.mixture}};
  return fit_junction_dynamics(problem, options);
}

// A junction process noise of 0.1 K²/s lets the filter's junction wander a kelvin in ten seconds
// after the case readings' rounding and noise (what a case log's misfit can ask for, the header);
// the twin's junction does not wander.
constexpr double kWanderingJunctionQj = 0.1;
constexpr double kLms200Qj = 1e-4;

TEST(JunctionDynamics, TheRangesRejectAWanderingJunctionAndNeverAdoptOne) {
  const JunctionNoiseCase c = datasheet_device();
  ASSERT_TRUE(c.trained.thermal.map.has_value());
  // The case log's q_j wanders; its start is the LMS 200 level: the ranges reject the move.
  const JunctionDynamicsFit rejected = judge_junction_noise(c, kWanderingJunctionQj, kLms200Qj);
  ASSERT_TRUE(rejected.held_junction_noise_start.has_value());
  EXPECT_TRUE(rejected.junction_noise_held)
      << "t " << rejected.noise_block_t << ", p " << rejected.noise_block_p;
  EXPECT_GT(rejected.held_junction_noise_start->ranges_log_likelihood,
            rejected.start.ranges_log_likelihood);
  ASSERT_TRUE(rejected.replaced) << "t " << rejected.block_t << ", p " << rejected.block_p;
  EXPECT_EQ(rejected.chosen_noise().junction_process_psd_k2_per_s, kLms200Qj);
  // The other way round: the case log's level is the LMS 200's and the start wanders: the
  // ranges keep the case log's level.
  const JunctionDynamicsFit kept = judge_junction_noise(c, kLms200Qj, kWanderingJunctionQj);
  EXPECT_FALSE(kept.junction_noise_held)
      << "t " << kept.noise_block_t << ", p " << kept.noise_block_p;
  EXPECT_EQ(kept.chosen_noise().junction_process_psd_k2_per_s, kLms200Qj);
}

TEST(JunctionDynamics, OnlyARaisedQjIsJudgedAndTheCalibrationsFilterHasTheVerdict) {
  const JunctionNoiseCase c = datasheet_device();
  ASSERT_TRUE(c.trained.junction_dynamics.has_value() && c.trained.kalman_noise_fit.has_value());
  const JunctionDynamicsFit& fit = *c.trained.junction_dynamics;
  const core::KalmanNoiseFit& log = *c.trained.kalman_noise_fit;
  const double case_log_q_j = log.noise.junction_process_psd_k2_per_s;
  const double start_q_j = log.start.junction_process_psd_k2_per_s;
  // The coarse sensor's case log lowers q_j below its start: the junction follows the thermal
  // model, and the ranges are not asked.
  ASSERT_LT(case_log_q_j, start_q_j);
  EXPECT_FALSE(fit.held_junction_noise_start.has_value());
  EXPECT_EQ(c.trained.calibration.kalman_noise.junction_process_psd_k2_per_s, case_log_q_j);
  ASSERT_TRUE(c.trained.calibration.choices.junction_dynamics.has_value());
  EXPECT_FALSE(c.trained.calibration.choices.junction_dynamics->junction_noise_held);
}

TEST(JunctionDynamics, TheAlternativeIsQjBackAtItsStartWhenTheLogRaisedIt) {
  core::KalmanNoiseFit log;
  log.start.junction_process_psd_k2_per_s = kLms200Qj;
  log.noise = log.start;
  log.noise.case_process_psd_k2_per_s = 3e-6;
  log.noise.measurement_variance_k2 = 6e-4;
  const auto junction = static_cast<std::size_t>(core::KalmanNoiseLevel::kJunctionProcess);
  log.noise.junction_process_psd_k2_per_s = kWanderingJunctionQj;  // raised
  const std::optional<core::ThermalNoise> held = held_junction_noise(log);
  ASSERT_TRUE(held.has_value());
  EXPECT_EQ(held->junction_process_psd_k2_per_s, kLms200Qj);
  EXPECT_EQ(held->case_process_psd_k2_per_s, 3e-6);  // the other levels stay the log's
  EXPECT_EQ(held->measurement_variance_k2, 6e-4);
  log.noise.junction_process_psd_k2_per_s = 1e-10;  // lowered
  EXPECT_FALSE(held_junction_noise(log).has_value());
  log.noise.junction_process_psd_k2_per_s = kLms200Qj;  // held
  log.levels[junction].held = true;
  EXPECT_FALSE(held_junction_noise(log).has_value());
}

TEST(JunctionDynamics, GivenLevelsAreNotJudged) {
  // Levels the user gives (--kalman-noise) are the calibration's; the ranges are not asked.
  TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  core::ThermalNoise given;
  given.junction_process_psd_k2_per_s = kWanderingJunctionQj;
  settings.kalman_noise = given;
  const Training t =
      train_calibration(test::twin_measured_data(scenario_with_junction(1.8, 10.8)), settings);
  ASSERT_TRUE(t.junction_dynamics.has_value());
  EXPECT_FALSE(t.junction_dynamics->held_junction_noise_start.has_value());
  EXPECT_FALSE(t.junction_dynamics->junction_noise_held);
  EXPECT_EQ(t.calibration.kalman_noise.junction_process_psd_k2_per_s, kWanderingJunctionQj);
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
