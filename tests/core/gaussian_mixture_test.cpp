#include "core/gaussian_mixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

// Eq. 18 worked by hand for one residual.
TEST(GaussianMixture, ResponsibilitiesAreEquation18) {
  const auto m = testing::mixture({-1.0, 2.0}, {0.5, 1.5}, {0.7, 0.3});
  const Eigen::Vector3d e(0.3, -1.2, 2.5);
  Eigen::MatrixXd r;
  const double ll = mixture_e_step(e, m, r);
  double expected_ll = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double a = 0.7 * testing::normal_pdf(e[k], -1.0, 0.25);
    const double b = 0.3 * testing::normal_pdf(e[k], 2.0, 2.25);
    EXPECT_NEAR(r(k, 1), b / (a + b), 1e-14);
    EXPECT_NEAR(r(k, 0) + r(k, 1), 1.0, 1e-15);
    expected_ll += std::log(a + b);
  }
  EXPECT_NEAR(ll, expected_ll, 1e-12);
}

// A residual 1e4 standard deviations out underflows every density in linear arithmetic; the
// log-sum-exp form still gives a finite likelihood and proper responsibilities.
TEST(GaussianMixture, FarTailsStayFinite) {
  const auto m = testing::mixture({0.0, 1.0}, {1.0, 1.0}, {0.5, 0.5});
  Eigen::MatrixXd r;
  const double ll = mixture_e_step(Eigen::Vector2d(1e4, -1e4), m, r);
  EXPECT_TRUE(std::isfinite(ll));
  EXPECT_NEAR(r(0, 1), 1.0, 1e-12);  // the far right point belongs to the right mode
  EXPECT_NEAR(r(1, 0), 1.0, 1e-12);
  EXPECT_TRUE(r.allFinite());
}

TEST(GaussianMixture, ValidateNamesTheProblem) {
  auto m = testing::mixture({0.0, 1.0}, {1.0, 1.0}, {0.5, 0.6});
  EXPECT_THROW(m.validate(), InvalidInput);
  m.weight << 0.5, 0.5;
  m.variance[1] = 0.0;
  EXPECT_THROW(m.validate(), InvalidInput);
  m.variance[1] = 1.0;
  m.mean.resize(3);
  EXPECT_THROW(m.validate(), InvalidInput);
}

// The probability of a rounded value under one standard normal mode, from the tail on the
// interval's side: P(|Z| < ½) at 0, Q(4.5) − Q(5.5) at ±5 (known values of Φ), and far beyond
// double precision the density times the width, log(1 · N(40; 0, 1)).
TEST(GaussianMixture, RoundedProbabilitiesAreTheIntervalsOfTheModes) {
  const auto single = testing::mixture({0.0}, {1.0}, {1.0});
  Eigen::VectorXd residual(4);
  residual << 0.0, 5.0, -5.0, 40.0;
  const Eigen::VectorXd p = rounded_mixture_log_probabilities(residual, single, 1.0);
  EXPECT_NEAR(p[0], std::log(0.38292492254802624), 1e-14);
  EXPECT_NEAR(p[1], std::log(3.3786835622641737e-06), 1e-12);
  EXPECT_NEAR(p[2], p[1], 1e-12);
  EXPECT_NEAR(p[3], -800.9189385332047, 1e-9);
  // Two modes: the weighted sum of the modes' intervals (the second centred on 5).
  const auto two = testing::mixture({0.0, 5.0}, {1.0, 1.0}, {0.25, 0.75});
  const Eigen::VectorXd q = rounded_mixture_log_probabilities(residual.head(2), two, 1.0);
  EXPECT_NEAR(q[0], std::log(0.25 * 0.38292492254802624 + 0.75 * 3.3786835622641737e-06), 1e-12);
  EXPECT_NEAR(q[1], std::log(0.25 * 3.3786835622641737e-06 + 0.75 * 0.38292492254802624), 1e-12);
  // The same per mode, on arrays: each range its own mean and spread.
  Eigen::ArrayXd mean(2), variance(2);
  mean << 0.0, 5.0;
  variance << 1.0, 4.0;
  const Eigen::ArrayXd per_mode =
      rounded_normal_log_probabilities(residual.head(2).array(), mean, variance, 2.0);
  EXPECT_NEAR(per_mode[0], std::log(0.6826894921370859), 1e-12);   // P(|Z| < 1)
  EXPECT_NEAR(per_mode[1], std::log(0.38292492254802624), 1e-12);  // P(|Z| < ½), σ = 2
}

}  // namespace
}  // namespace tofcomp::core

namespace tofcomp::core {
namespace {

// Dropping a mode keeps the others' means and variances and renormalizes their weights.
TEST(GaussianMixture, WithoutModeRenormalizesTheOthers) {
  const MixtureParameters m{Eigen::Vector3d(-1.0, 2.0, 40.0), Eigen::Vector3d(0.25, 0.5, 1.0),
                            Eigen::Vector3d(0.3, 0.5, 0.2)};
  const MixtureParameters two = without_mode(m, 2);
  EXPECT_EQ(two.mean, Eigen::Vector2d(-1.0, 2.0));
  EXPECT_EQ(two.variance, Eigen::Vector2d(0.25, 0.5));
  EXPECT_NEAR(two.weight[0], 0.375, 1e-15);
  EXPECT_NEAR(two.weight[1], 0.625, 1e-15);
  EXPECT_EQ(without_mode(m, 0).mean, Eigen::Vector2d(2.0, 40.0));
  EXPECT_THROW(without_mode(m, 3), InvalidInput);
  EXPECT_THROW(without_mode(m, -1), InvalidInput);
  const MixtureParameters one{Eigen::VectorXd::Constant(1, 0.0), Eigen::VectorXd::Constant(1, 1.0),
                              Eigen::VectorXd::Constant(1, 1.0)};
  EXPECT_THROW(without_mode(one, 0), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
