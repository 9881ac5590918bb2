#include "core/kalman_noise_fit.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "core/error.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::core {
namespace {

// An LMS 200-like network: junction lag R1 C1 ≈ 11 s, case time constant R2 C2 ≈ 17 min.
ThermalParameters lms_like() { return ThermalParameters{0.18, 0.5, 60.0, 2000.0, 10.0}; }

// A 1 Hz case log drawn from the filter's own model (Eq. 5 with process noise of PSDs q_c, q_j
// and a sensor of variance r): power cycled 40 min on, 20 min off, in a 22 °C room.
CaseTemperatureLog draw_log(const ThermalParameters& p, const ThermalNoise& truth,
                            Eigen::Index seconds, unsigned seed) {
  constexpr double kStepS = 1.0;
  const DiscreteThermalModel step = discretize_zoh(p, kStepS);
  const Eigen::Matrix2d q = process_noise_covariance(p, truth, kStepS);
  const Eigen::Matrix2d q_root = Eigen::LLT<Eigen::Matrix2d>(q).matrixL();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> standard(0.0, 1.0);
  CaseTemperatureLog log;
  log.times_s = Eigen::VectorXd::LinSpaced(seconds, 0.0, static_cast<double>(seconds - 1));
  log.power_on_fraction.resize(seconds);
  log.ambient_c = Eigen::VectorXd::Constant(seconds, 22.0);
  log.case_c.resize(seconds);
  Eigen::Vector2d x(22.0, 22.0);
  for (Eigen::Index k = 0; k < seconds; ++k) {
    log.power_on_fraction[k] = (k % 3600) < 2400 ? 1.0 : 0.0;
    log.case_c[k] = x[0] + std::sqrt(truth.measurement_variance_k2) * standard(rng);
    const Eigen::Vector2d w = q_root * Eigen::Vector2d(standard(rng), standard(rng));
    x = step.a * x + step.b_power * log.power_on_fraction[k] + step.b_ambient * 22.0 + w;
  }
  return log;
}

ThermalNoise noisy_sensor() {
  ThermalNoise truth;
  truth.case_process_psd_k2_per_s = 1e-5;
  truth.junction_process_psd_k2_per_s = 1e-4;
  truth.measurement_variance_k2 = 0.01;  // σ = 0.1 °C: a coarse, noisy sensor
  return truth;
}

// The levels the log was drawn with are recovered from a start far from them (the LMS 200
// defaults: r 30 times too small, q_c 10 times).
TEST(KalmanNoiseFit, RecoversTheSensorAndCaseLevelsTheLogWasDrawnWith) {
  const ThermalNoise truth = noisy_sensor();
  const CaseTemperatureLog log = draw_log(lms_like(), truth, 6 * 3600, 7);
  const KalmanNoiseFit fit = fit_kalman_noise(log, lms_like(), ThermalNoise{});
  EXPECT_NEAR(fit.noise.measurement_variance_k2, truth.measurement_variance_k2, 0.05 * 0.01);
  EXPECT_GT(fit.noise.case_process_psd_k2_per_s, truth.case_process_psd_k2_per_s / 2.0);
  EXPECT_LT(fit.noise.case_process_psd_k2_per_s, truth.case_process_psd_k2_per_s * 2.0);
  const auto sensor = static_cast<std::size_t>(KalmanNoiseLevel::kSensor);
  EXPECT_FALSE(fit.levels[sensor].held);
  // The maximum is a maximum: the likelihood at the truth is not above it, and the start's is
  // far below.
  EXPECT_GE(fit.log_likelihood, innovations_log_likelihood(log, lms_like(), truth) - 1e-6);
  EXPECT_GT(fit.log_likelihood, fit.start_log_likelihood + 1000.0);
}

// A level the log cannot see stays at the start and is reported held: the junction's process
// noise reaches the case only through R1 C2, and a log this short does not resolve it.
TEST(KalmanNoiseFit, HoldsALevelTheLogDoesNotDetermine) {
  const ThermalNoise truth = noisy_sensor();
  const CaseTemperatureLog log = draw_log(lms_like(), truth, 1800, 11);
  ThermalNoise start;
  start.junction_process_psd_k2_per_s = 3e-4;
  const KalmanNoiseFit fit = fit_kalman_noise(log, lms_like(), start);
  const auto junction = static_cast<std::size_t>(KalmanNoiseLevel::kJunctionProcess);
  EXPECT_TRUE(fit.levels[junction].held);
  EXPECT_EQ(fit.noise.junction_process_psd_k2_per_s, 3e-4);
  EXPECT_LT(fit.levels[junction].profile_drop_down, NoiseFitOptions{}.determined_drop);
  EXPECT_LT(fit.levels[junction].profile_drop_up, NoiseFitOptions{}.determined_drop);
}

TEST(KalmanNoiseFit, RefusesALogTooShortToJudge) {
  CaseTemperatureLog log;
  log.times_s = Eigen::Vector2d(0.0, 1.0);
  log.power_on_fraction = Eigen::Vector2d(1.0, 1.0);
  log.ambient_c = Eigen::Vector2d(22.0, 22.0);
  log.case_c = Eigen::Vector2d(22.0, 22.1);
  EXPECT_THROW(fit_kalman_noise(log, lms_like(), ThermalNoise{}), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
