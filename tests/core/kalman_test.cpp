#include "core/kalman.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <random>
#include <unsupported/Eigen/KroneckerProduct>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "core/error.hpp"
#include "tests/support/thermal_examples.hpp"

namespace tofcomp::core {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

struct ThermalLog {
  Eigen::VectorXd times, power, ambient, reading;
  std::vector<bool> measured;
};

// A small irregular record with gaps in the readings.
ThermalLog small_record() {
  ThermalLog r;
  r.times = (Eigen::VectorXd(12) << 0, 0.7, 2, 2.5, 4.1, 6, 6.3, 9, 12, 12.4, 15, 20).finished();
  r.power = (Eigen::VectorXd(12) << 1, 1, 1, 0, 0, 1, 1, 0.5, 0, 0, 1, 1).finished();
  r.ambient =
      (Eigen::VectorXd(12) << 22, 22.1, 22.3, 22.2, 22, 21.8, 21.9, 22, 22.4, 22.5, 22.3, 22.2)
          .finished();
  r.reading = (Eigen::VectorXd(12) << 22.4, kNan, 23.1, 23.0, kNan, kNan, 23.6, kNan, 23.2, 23.3,
               kNan, 24.0)
                  .finished();
  for (Eigen::Index i = 0; i < 12; ++i) r.measured.push_back(!std::isnan(r.reading[i]));
  return r;
}

ThermalNoise loud_noise() {
  ThermalNoise n;
  n.case_process_psd_k2_per_s = 1e-3;
  n.junction_process_psd_k2_per_s = 5e-3;
  n.measurement_variance_k2 = 0.01;
  return n;
}

// No process noise: the model is exact; readings with a 0.05 K standard deviation.
ThermalNoise sensor_noise_only() {
  ThermalNoise n;
  n.case_process_psd_k2_per_s = 0.0;
  n.junction_process_psd_k2_per_s = 0.0;
  n.measurement_variance_k2 = 0.05 * 0.05;
  return n;
}

ThermalBelief prior() {
  ThermalBelief b;
  b.mean = Eigen::Vector2d(22.3, 24.0);
  b.covariance << 0.04, 0.01, 0.01, 0.5;
  return b;
}

// Q_T by Simpson's rule on ∫_0^T e^{As} Q_c e^{Aᵀs} ds.
TEST(KalmanProcessNoise, VanLoanEqualsQuadrature) {
  const ThermalParameters p = testing::round_thermal_parameters();
  const ThermalNoise n = loud_noise();
  const Eigen::Matrix2d a = continuous_model(p).a;
  const Eigen::Matrix2d qc = Eigen::Vector2d(1e-3, 5e-3).asDiagonal();
  for (const double step : {0.05, 5.0, 40.0}) {
    const int intervals = 2000;
    const double h = step / intervals;
    Eigen::Matrix2d integral = Eigen::Matrix2d::Zero();
    for (int i = 0; i <= intervals; ++i) {
      const Eigen::Matrix2d e = (a * (h * i)).exp();
      const double w = (i == 0 || i == intervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      integral += w * e * qc * e.transpose();
    }
    integral *= h / 3.0;
    const Eigen::Matrix2d q = process_noise_covariance(p, n, step);
    EXPECT_LT((q - integral).norm(), 1e-10 * integral.norm()) << step;
    EXPECT_EQ(q(0, 1), q(1, 0));
  }
  EXPECT_EQ(process_noise_covariance(p, n, 0.0), Eigen::Matrix2d::Zero());
}

// Over long steps Q_T = P∞ − Φ P∞ Φᵀ, with P∞ solving A P + P Aᵀ + Q_c = 0 (the stationary
// covariance): checks the doubling that keeps long gaps finite.
TEST(KalmanProcessNoise, LongStepsReachTheStationaryCovariance) {
  const ThermalParameters p = lms200_example_parameters();
  const ThermalNoise n;
  const Eigen::Matrix2d a = continuous_model(p).a;
  const Eigen::Matrix2d qc =
      Eigen::Vector2d(n.case_process_psd_k2_per_s, n.junction_process_psd_k2_per_s).asDiagonal();
  const Eigen::Matrix4d lyapunov = Eigen::kroneckerProduct(Eigen::Matrix2d::Identity(), a) +
                                   Eigen::kroneckerProduct(a, Eigen::Matrix2d::Identity());
  const Eigen::Vector4d vec_qc = Eigen::Map<const Eigen::Vector4d>(qc.data());
  const Eigen::Vector4d vec_p = lyapunov.fullPivLu().solve(-vec_qc);
  const Eigen::Matrix2d stationary = Eigen::Map<const Eigen::Matrix2d>(vec_p.data());
  for (const double step : {600.0, 3600.0, 8.0 * 3600.0, 1e7}) {
    const Eigen::Matrix2d phi = (a * step).exp();
    const Eigen::Matrix2d expected = stationary - phi * stationary * phi.transpose();
    const Eigen::Matrix2d q = process_noise_covariance(p, n, step);
    EXPECT_TRUE(q.allFinite());
    EXPECT_LT((q - expected).norm(), 1e-9 * expected.norm()) << step;
  }
}

// The smoother's means and junction standard deviations equal the batch weighted least-squares
// solution of the same linear-Gaussian problem: all states stacked, with the prior, every
// dynamics step (weight Q_k⁻¹) and every available reading (weight 1/r) as equations.
TEST(KalmanSmoother, EqualsBatchWeightedLeastSquares) {
  const ThermalParameters p = testing::round_thermal_parameters();
  const ThermalNoise n = loud_noise();
  const ThermalBelief b = prior();
  const ThermalLog r = small_record();
  const Eigen::Index k = r.times.size();

  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(2 * k, 2 * k);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * k);
  auto add = [&](const Eigen::MatrixXd& rows, const Eigen::MatrixXd& weight,
                 const Eigen::VectorXd& target) {
    information += rows.transpose() * weight * rows;
    rhs += rows.transpose() * weight * target;
  };
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(2, 2 * k);
  rows.leftCols(2).setIdentity();
  add(rows, b.covariance.inverse(), b.mean);
  for (Eigen::Index i = 0; i + 1 < k; ++i) {
    const DiscreteThermalModel d = discretize_zoh(p, r.times[i + 1] - r.times[i]);
    rows.setZero();
    rows.block(0, 2 * i, 2, 2) = -d.a;
    rows.block(0, 2 * i + 2, 2, 2).setIdentity();
    const Eigen::Vector2d input = d.b_power * r.power[i] + d.b_ambient * r.ambient[i];
    add(rows, process_noise_covariance(p, n, r.times[i + 1] - r.times[i]).inverse(), input);
  }
  for (Eigen::Index i = 0; i < k; ++i) {
    if (!r.measured[static_cast<std::size_t>(i)]) continue;
    Eigen::MatrixXd row = Eigen::MatrixXd::Zero(1, 2 * k);
    row(0, 2 * i) = 1.0;
    add(row, Eigen::MatrixXd::Constant(1, 1, 1.0 / n.measurement_variance_k2),
        Eigen::VectorXd::Constant(1, r.reading[i]));
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(information);
  const Eigen::VectorXd batch = llt.solve(rhs);
  const Eigen::MatrixXd covariance = llt.solve(Eigen::MatrixXd::Identity(2 * k, 2 * k));

  const SmoothedThermalRecord s =
      smooth_thermal_record(p, n, b, r.times, r.power, r.ambient, r.reading, r.measured);
  for (Eigen::Index i = 0; i < k; ++i) {
    EXPECT_NEAR(s.case_mean_c[i], batch[2 * i], 1e-9) << i;
    EXPECT_NEAR(s.junction_mean_c[i], batch[2 * i + 1], 1e-9) << i;
    EXPECT_NEAR(s.case_std_c[i], std::sqrt(covariance(2 * i, 2 * i)), 1e-9) << i;
    EXPECT_NEAR(s.junction_std_c[i], std::sqrt(covariance(2 * i + 1, 2 * i + 1)), 1e-9) << i;
  }
}

// The last smoothed estimate conditions on the same readings as the filter's last estimate.
TEST(KalmanSmoother, LastEstimateIsTheFilters) {
  const ThermalParameters p = testing::round_thermal_parameters();
  const ThermalNoise n = loud_noise();
  const ThermalLog r = small_record();
  ThermalKalmanFilter filter(p, n, prior());
  for (Eigen::Index i = 0; i < r.times.size(); ++i) {
    if (i > 0) filter.predict(r.times[i] - r.times[i - 1], r.power[i - 1], r.ambient[i - 1]);
    if (r.measured[static_cast<std::size_t>(i)]) filter.update(r.reading[i]);
  }
  const SmoothedThermalRecord s =
      smooth_thermal_record(p, n, prior(), r.times, r.power, r.ambient, r.reading, r.measured);
  const Eigen::Index last = r.times.size() - 1;
  EXPECT_NEAR(filter.case_mean_c(), s.case_mean_c[last], 1e-12);
  EXPECT_NEAR(filter.junction_mean_c(), s.junction_mean_c[last], 1e-12);
  EXPECT_NEAR(filter.junction_std_c(), s.junction_std_c[last], 1e-12);
  EXPECT_NEAR(filter.log_likelihood(), s.log_likelihood, 1e-12);
  EXPECT_TRUE(std::isfinite(s.log_likelihood));
}

// A state known to within 1e-7 K in the case and 1e-15 K in the junction under no process noise:
// every predicted covariance is near singular (the smoother takes the pseudo-inverse, not
// Cholesky), and the smoother returns the model's own noise-free trajectory, finite, whatever
// the readings say.
TEST(KalmanSmoother, AStateKnownExactlyStaysOnTheModelsTrajectory) {
  const ThermalParameters p = lms200_example_parameters();
  const ThermalNoise n = sensor_noise_only();
  const Eigen::Index k = 600;
  Eigen::VectorXd times(k), u(k), ta(k), reading(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    times[i] = static_cast<double>(i);
    u[i] = (i / 200) % 2 == 0 ? 1.0 : 0.0;
    ta[i] = 22.0;
  }
  const Eigen::Vector2d start(24.0, 27.0);
  const ThermalTrajectory truth = simulate(discretize_zoh(p, 1.0), start, u, ta);
  reading = truth.case_c.array() + 0.3;  // readings off the model: they cannot move a known state
  ThermalBelief known;
  known.mean = start;
  known.covariance << 1e-14, 0.0, 0.0, 1e-30;
  const SmoothedThermalRecord s =
      smooth_thermal_record(p, n, known, times, u, ta, reading, std::vector<bool>(k, true));
  for (Eigen::Index i = 0; i < k; ++i) {
    ASSERT_NEAR(s.junction_mean_c[i], truth.junction_c[i], 1e-6) << i;
    ASSERT_NEAR(s.case_mean_c[i], truth.case_c[i], 1e-6) << i;
    ASSERT_TRUE(std::isfinite(s.junction_std_c[i])) << i;
  }
}

// Without process noise the model is exact, so many readings pin the junction to the truth.
TEST(ThermalKalmanFilter, ConvergesToTheTruthWithoutProcessNoise) {
  const ThermalParameters p = lms200_example_parameters();
  const ThermalNoise n = sensor_noise_only();
  const Eigen::Index k = 7200;
  Eigen::VectorXd u(k);
  for (Eigen::Index i = 0; i < k; ++i) u[i] = (i / 900) % 2 == 0 ? 1.0 : 0.0;
  const Eigen::VectorXd ta = Eigen::VectorXd::Constant(k, 22.0);
  const ThermalTrajectory truth =
      simulate(discretize_zoh(p, 1.0), Eigen::Vector2d(24.0, 27.0), u, ta);
  std::mt19937_64 rng(21);
  std::normal_distribution<double> noise(0.0, 0.05);
  // The prior is 1-2 K off: at rest with the first reading, junction ± 2 K.
  ThermalKalmanFilter filter(p, n, prior_at_case_temperature(p, truth.case_c[0], ta[0], 0.1));
  for (Eigen::Index i = 0; i < k; ++i) {
    if (i > 0) filter.predict(1.0, u[i - 1], ta[i - 1]);
    filter.update(truth.case_c[i] + noise(rng));
  }
  EXPECT_NEAR(filter.junction_mean_c(), truth.junction_c[k - 1], 0.01);
  EXPECT_NEAR(filter.case_mean_c(), truth.case_c[k - 1], 0.01);
  EXPECT_LT(filter.junction_std_c(), 0.01);
  EXPECT_GT(filter.junction_std_c(), 0.0);
}

// Ranges at 10 Hz, case readings at 1 Hz quantized to 0.0625 °C, the laser switched on from cold
// at the first instant: the smoother gives the junction at every instant, its first minute too
// (where the first quantized readings once made it start kelvins too hot), and the unmeasured
// instants may hold NaN.
TEST(KalmanSmoother, MixedRateRecordGivesTheJunctionEverywhere) {
  const ThermalParameters p = lms200_example_parameters();
  const Eigen::Index k = 30 * 60 * 10;
  const Eigen::VectorXd times =
      Eigen::VectorXd::LinSpaced(k, 0.0, 0.1 * static_cast<double>(k - 1));
  Eigen::VectorXd u(k);
  for (Eigen::Index i = 0; i < k; ++i) u[i] = (i / 3000) % 2 == 0 ? 1.0 : 0.0;
  const Eigen::VectorXd ta = Eigen::VectorXd::Constant(k, 22.0);
  // The truth starts at rest with the laser off: junction and case at the ambient.
  const ThermalTrajectory truth =
      simulate_at_times(p, equilibrium_state(p, 0.0, ta[0]), times, u, ta);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  Eigen::VectorXd reading = Eigen::VectorXd::Constant(k, kNan);
  std::vector<bool> measured(static_cast<std::size_t>(k), false);
  for (Eigen::Index i = 0; i < k; i += 10) {
    reading[i] = 0.0625 * std::round((truth.case_c[i] + noise(rng)) / 0.0625);
    measured[static_cast<std::size_t>(i)] = true;
  }
  const ThermalNoise n;
  const SmoothedThermalRecord s = smooth_thermal_record(
      p, n, prior_at_case_temperature(p, reading[0], ta[0], 0.05), times, u, ta, reading, measured);
  ASSERT_EQ(s.junction_mean_c.size(), k);
  EXPECT_TRUE(s.junction_mean_c.allFinite());
  EXPECT_TRUE(s.junction_std_c.allFinite());
  EXPECT_GT(s.junction_std_c.minCoeff(), 0.0);
  const double rms = std::sqrt((s.junction_mean_c - truth.junction_c).squaredNorm() / k);
  EXPECT_LT(rms, 0.05);
  const Eigen::Index first_minute = 600;
  EXPECT_LT((s.junction_mean_c - truth.junction_c).head(first_minute).cwiseAbs().maxCoeff(),
            0.25 * p.power_w * p.r1_k_per_w);
  // Between two readings the smoother interpolates: no instant is off by more than a few σ.
  const Eigen::ArrayXd z =
      (s.junction_mean_c - truth.junction_c).array() / s.junction_std_c.array();
  EXPECT_LT(z.abs().maxCoeff(), 6.0);
}

TEST(ThermalKalmanFilter, BadInputThrowsAndLeavesTheStateAlone) {
  const ThermalParameters p = testing::round_thermal_parameters();
  ThermalKalmanFilter filter(p, loud_noise(), prior());
  filter.predict(0.5, 1.0, 22.0);
  const ThermalBelief before = filter.belief();
  EXPECT_THROW(filter.predict(-0.1, 1.0, 22.0), InvalidInput);
  EXPECT_THROW(filter.predict(kNan, 1.0, 22.0), InvalidInput);
  EXPECT_THROW(filter.predict(0.1, 1.5, 22.0), InvalidInput);
  EXPECT_THROW(filter.predict(0.1, 1.0, INFINITY), InvalidInput);
  EXPECT_THROW(filter.update(kNan), InvalidInput);
  EXPECT_EQ(filter.belief().mean, before.mean);
  EXPECT_EQ(filter.belief().covariance, before.covariance);
  filter.predict(0.0, 1.0, 22.0);  // a zero step changes nothing
  EXPECT_EQ(filter.belief().mean, before.mean);

  ThermalNoise bad = loud_noise();
  bad.junction_process_psd_k2_per_s = -1.0;
  EXPECT_THROW(ThermalKalmanFilter(p, bad, prior()), InvalidInput);
  bad = loud_noise();
  bad.measurement_variance_k2 = 0.0;
  EXPECT_THROW(ThermalKalmanFilter(p, bad, prior()), InvalidInput);
  ThermalBelief singular = prior();
  singular.covariance << 1.0, 1.0, 1.0, 1.0;
  EXPECT_THROW(ThermalKalmanFilter(p, loud_noise(), singular), InvalidInput);

  ThermalLog r = small_record();
  r.reading[0] = kNan;  // NaN at a measured instant
  EXPECT_THROW(smooth_thermal_record(p, loud_noise(), prior(), r.times, r.power, r.ambient,
                                     r.reading, r.measured),
               InvalidInput);
  r = small_record();
  r.measured.pop_back();
  EXPECT_THROW(smooth_thermal_record(p, loud_noise(), prior(), r.times, r.power, r.ambient,
                                     r.reading, r.measured),
               InvalidInput);
  r = small_record();
  r.times[5] = 1.0;  // backwards
  EXPECT_THROW(smooth_thermal_record(p, loud_noise(), prior(), r.times, r.power, r.ambient,
                                     r.reading, r.measured),
               InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
