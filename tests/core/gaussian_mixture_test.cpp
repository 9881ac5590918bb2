#include "core/gaussian_mixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

double normal_pdf(double x, double mean, double variance) {
  return std::exp(-(x - mean) * (x - mean) / (2 * variance)) /
         std::sqrt(2 * std::numbers::pi * variance);
}

// Eq. 18 worked by hand for one residual.
TEST(GaussianMixture, ResponsibilitiesAreEquation18) {
  const auto m = testing::mixture({-1.0, 2.0}, {0.5, 1.5}, {0.7, 0.3});
  const Eigen::Vector3d e(0.3, -1.2, 2.5);
  Eigen::MatrixXd r;
  const double ll = mixture_e_step(e, m, r);
  double expected_ll = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double a = 0.7 * normal_pdf(e[k], -1.0, 0.25);
    const double b = 0.3 * normal_pdf(e[k], 2.0, 2.25);
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

}  // namespace
}  // namespace tofcomp::core
