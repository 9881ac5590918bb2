// SQUAREM in the extended EM (core/extended_em.hpp): the fixed point of the plain ECM map (the
// same log-likelihood and parameters) under a mode chain, binned weights and spreads with a bias
// column, and an outlier component; fewer applications of the map; the log-likelihood never
// decreasing along the points moved to where the map is an ECM (without a chain).
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <random>

#include "core/extended_em.hpp"

namespace tofcomp::core {
namespace {

constexpr double kTightTolerance = 1e-13;  // per range
constexpr int kIterationCap = 20000;

MixtureParameters overlapping_two_modes() {
  MixtureParameters m;
  m.mean = Eigen::Vector2d(-0.7, 0.8);
  m.variance = Eigen::Vector2d(0.6, 0.9);
  m.weight = Eigen::Vector2d(0.55, 0.45);
  return m;
}

Term bins_split_at(Parameter parameter, double edge) {
  Term t;
  t.parameter = parameter;
  t.covariate = Covariate::JunctionTemperature;
  t.form = Form::Bins;
  t.knots = Eigen::VectorXd::Constant(1, edge);
  return t;
}

struct ExtendedProblem {
  ExtendedDesign design;
  Eigen::VectorXd y;
  ExtendedParameters start;
};

// Two overlapping modes following a chain, a bias column, and no other extension.
ExtendedProblem chain_problem() {
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Index k = 8000;
  const MixtureParameters truth = overlapping_two_modes();
  ExtendedProblem p;
  p.design.shared.resize(k, 1);
  p.design.mode_columns.resize(2);
  p.design.state = Eigen::VectorXi::Zero(k);
  p.y.resize(k);
  int mode = 0;
  for (Eigen::Index i = 0; i < k; ++i) {
    if (u(rng) > (mode == 0 ? 0.9 : 0.85)) mode = 1 - mode;
    p.design.shared(i, 0) = std::sin(0.001 * static_cast<double>(i));
    p.y[i] =
        0.5 * p.design.shared(i, 0) + truth.mean[mode] + std::sqrt(truth.variance[mode]) * n(rng);
  }
  ExtendedMixture start = without_extensions(overlapping_two_modes());
  start.modes.mean = Eigen::Vector2d(-1.0, 1.0);
  start.transition = Eigen::Matrix2d::Constant(0.5);
  p.start = {Eigen::VectorXd::Zero(1), std::vector<Eigen::VectorXd>(2), start};
  return p;
}

// Weights and spreads per temperature bin, a bias column, and outliers.
ExtendedProblem binned_outlier_problem() {
  std::mt19937_64 rng(62);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Index k = 12000;
  ExtendedProblem p;
  p.design.shared.resize(k, 1);
  p.design.mode_columns.resize(2);
  p.design.state.resize(k);
  p.y.resize(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double t = 24.0 + 4.0 * u(rng);
    const int bin = t >= 26.0;
    p.design.shared(i, 0) = t - 26.0;
    p.design.state[i] = bin * 2 + bin;
    const int mode = u(rng) < (bin ? 0.6 : 0.3) ? 1 : 0;
    p.y[i] = u(rng) < 0.02 ? -40.0 + 80.0 * u(rng)
                           : -0.8 * (t - 26.0) + (mode ? 0.8 : -0.7) + (bin ? 0.9 : 0.6) * n(rng);
  }
  ExtendedMixture start = without_extensions(overlapping_two_modes());
  start.weight_bins = NoiseBins{
      bins_split_at(Parameter::Weights, 26.0), Eigen::MatrixXd::Constant(2, 2, 0.5), {}, {}};
  start.variance_bins =
      NoiseBins{bins_split_at(Parameter::Spread, 26.0), Eigen::MatrixXd::Ones(2, 2), {}, {}};
  start.outlier_weight = 0.05;
  start.outlier_density = 1.0 / 80.0;
  p.start = {Eigen::VectorXd::Zero(1), std::vector<Eigen::VectorXd>(2), start};
  return p;
}

ExtendedEmResult fit_extended(const ExtendedProblem& p, EmAcceleration acceleration) {
  ExtendedEmOptions options;
  options.acceleration = acceleration;
  options.log_likelihood_tolerance = kTightTolerance;
  options.max_iterations = kIterationCap;
  return train_extended_em(p.design, p.y, p.start, options);
}

void expect_same_fit(const ExtendedEmResult& fast, const ExtendedEmResult& plain) {
  const double k = 1e4;
  EXPECT_NEAR(fast.log_likelihood, plain.log_likelihood, 1e-7 * k);
  EXPECT_NEAR(fast.fit.theta[0], plain.fit.theta[0], 1e-4);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(fast.fit.model.modes.mean[i], plain.fit.model.modes.mean[i], 1e-4) << i;
    EXPECT_NEAR(fast.fit.model.modes.variance[i], plain.fit.model.modes.variance[i], 1e-4) << i;
  }
}

void expect_monotone(const ExtendedEmResult& fit) {
  for (std::size_t i = 1; i < fit.log_likelihood_trace.size(); ++i) {
    EXPECT_GE(fit.log_likelihood_trace[i],
              fit.log_likelihood_trace[i - 1] - 1e-12 * std::abs(fit.log_likelihood_trace[i]))
        << std::setprecision(17) << "point " << i << ": " << fit.log_likelihood_trace[i]
        << " after " << fit.log_likelihood_trace[i - 1];
  }
}

TEST(ExtendedEmAcceleration, ChainReachesThePlainFixedPoint) {
  const ExtendedProblem p = chain_problem();
  const ExtendedEmResult plain = fit_extended(p, EmAcceleration::None);
  const ExtendedEmResult fast = fit_extended(p, EmAcceleration::Squarem);
  ASSERT_TRUE(plain.converged);
  ASSERT_TRUE(fast.converged);
  expect_same_fit(fast, plain);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(fast.fit.model.transition(i, i), plain.fit.model.transition(i, i), 1e-5) << i;
  }
  // Plain EM is quick on this chain already; the chain's initial law is updated to the mean
  // responsibility, not maximized, so the map is not monotone and its trace is not checked.
  EXPECT_GE(static_cast<double>(plain.iterations), 1.3 * fast.iterations)
      << "plain " << plain.iterations << ", SQUAREM " << fast.iterations;
}

TEST(ExtendedEmAcceleration, BinsAndOutliersReachThePlainFixedPoint) {
  const ExtendedProblem p = binned_outlier_problem();
  const ExtendedEmResult plain = fit_extended(p, EmAcceleration::None);
  const ExtendedEmResult fast = fit_extended(p, EmAcceleration::Squarem);
  ASSERT_TRUE(plain.converged);
  ASSERT_TRUE(fast.converged);
  expect_same_fit(fast, plain);
  EXPECT_NEAR(fast.fit.model.outlier_weight, plain.fit.model.outlier_weight, 1e-6);
  for (int b = 0; b < 2; ++b) {
    EXPECT_NEAR(fast.fit.model.weight_bins->table(b, 1), plain.fit.model.weight_bins->table(b, 1),
                1e-5);
    EXPECT_NEAR(fast.fit.model.variance_bins->table(b, 0),
                plain.fit.model.variance_bins->table(b, 0), 1e-4);
  }
  EXPECT_GE(plain.iterations, 2 * fast.iterations)
      << "plain " << plain.iterations << ", SQUAREM " << fast.iterations;
  expect_monotone(fast);
}

}  // namespace
}  // namespace tofcomp::core
