#include "core/statistical_tests.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

// Reference values: the χ² and normal quantiles printed in every statistics table, and closed
// forms (Q(1, x) = e^{−x}; for two degrees of freedom P(χ² > x) = e^{−x/2}).
TEST(StatisticalTests, TailsMatchTables) {
  EXPECT_NEAR(chi_square_survival(3.841458820694124, 1), 0.05, 1e-12);
  EXPECT_NEAR(chi_square_survival(18.307038053275146, 10), 0.05, 1e-12);
  EXPECT_NEAR(chi_square_survival(2.0, 2), std::exp(-1.0), 1e-14);
  EXPECT_NEAR(chi_square_survival(124.34211340400407, 100), 0.05, 1e-10);
  EXPECT_NEAR(regularized_upper_gamma(1.0, 7.5), std::exp(-7.5), 1e-15);
  EXPECT_NEAR(regularized_upper_gamma(1.0, 0.3), std::exp(-0.3), 1e-15);
  EXPECT_NEAR(two_sided_normal_p(1.959963984540054), 0.05, 1e-14);
  EXPECT_THROW(regularized_upper_gamma(0.0, 1.0), InvalidInput);
}

// Student's upper tail: closed forms for one degree of freedom (Cauchy, 1/2 − atan(t)/π) and two
// (1/2 − t / (2√(2 + t²))), a table's quantile, and the infinite t a constant positive gain gives.
TEST(StatisticalTests, StudentTailMatchesClosedFormsAndTables) {
  for (const double t : {-3.0, 0.0, 0.7, 12.0}) {
    EXPECT_NEAR(student_upper_tail(t, 1.0), 0.5 - std::atan(t) / std::numbers::pi, 1e-14) << t;
    EXPECT_NEAR(student_upper_tail(t, 2.0), 0.5 - t / (2.0 * std::sqrt(2.0 + t * t)), 1e-14) << t;
  }
  EXPECT_NEAR(student_upper_tail(1.812461122811676, 10.0), 0.05, 1e-12);
  EXPECT_EQ(student_upper_tail(std::numeric_limits<double>::infinity(), 5.0), 0.0);
  EXPECT_EQ(student_upper_tail(-std::numeric_limits<double>::infinity(), 5.0), 1.0);
}

TEST(StatisticalTests, LjungBoxByHand) {
  const Eigen::Vector4d alternating(1, -1, 1, -1);
  const TestResult r = ljung_box(alternating, 1);  // ρ1 = −3/4, Q = 4·6·(9/16)/3
  EXPECT_NEAR(r.statistic, 4.5, 1e-12);
  EXPECT_NEAR(r.p_value, chi_square_survival(4.5, 1), 1e-15);
}

// White noise: the 5 % test rejects about 5 % of the time; AR(1) with φ = 0.5 always.
TEST(StatisticalTests, LjungBoxSizeAndPower) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n01;
  int rejections = 0;
  const int runs = 400;
  for (int run = 0; run < runs; ++run) {
    Eigen::VectorXd white(500), ar(500);
    double previous = 0.0;
    for (int k = 0; k < 500; ++k) {
      white[k] = n01(rng);
      previous = 0.5 * previous + n01(rng);
      ar[k] = previous;
    }
    rejections += ljung_box(white, 10).p_value < 0.05;
    EXPECT_LT(ljung_box(ar, 10).p_value, 1e-10);
  }
  EXPECT_NEAR(rejections / static_cast<double>(runs), 0.05, 0.03);
}

TEST(StatisticalTests, RunsTest) {
  Eigen::VectorXi labels(6);
  labels << 0, 0, 1, 1, 0, 1;  // 4 runs; mean 2·3·3/6 + 1 = 4
  EXPECT_NEAR(runs_test(labels).statistic, 0.0, 1e-12);
  Eigen::VectorXi blocks(200);
  for (int k = 0; k < 200; ++k) blocks[k] = (k / 20) % 2;  // 10 long runs: persistence
  const TestResult r = runs_test(blocks);
  EXPECT_LT(r.statistic, -10.0);
  EXPECT_LT(r.p_value, 1e-20);
  Eigen::VectorXi one_kind = Eigen::VectorXi::Zero(10);
  EXPECT_THROW(runs_test(one_kind), NumericalError);
}

TEST(StatisticalTests, CorrelationAndIndependence) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(50, 0.0, 1.0);
  EXPECT_NEAR(correlation_test(x, 2.0 * x).statistic, 1.0, 1e-12);
  EXPECT_LT(correlation_test(x, 2.0 * x).p_value, 1e-100);
  Eigen::Matrix2d table;
  table << 10, 20, 30, 40;  // expected 12, 18, 28, 42
  const TestResult c = chi_square_independence(table);
  EXPECT_NEAR(c.statistic, 4.0 / 12 + 4.0 / 18 + 4.0 / 28 + 4.0 / 42, 1e-12);
  EXPECT_EQ(c.degrees_of_freedom, 1.0);
  const TestResult lr = likelihood_ratio_test(-100.0, -98.0, 1);
  EXPECT_DOUBLE_EQ(lr.statistic, 4.0);
  EXPECT_NEAR(lr.p_value, chi_square_survival(4.0, 1), 1e-15);
  // 30 values beyond a 1 % bound among 1000: 3× the expected 10.
  const TestResult tail = tail_excess_test(30, 1000, 0.01);
  EXPECT_DOUBLE_EQ(tail.statistic, 3.0);
  EXPECT_LT(tail.p_value, 1e-6);
  EXPECT_GT(tail_excess_test(10, 1000, 0.01).p_value, 0.3);
  // Poisson tails by hand: P(X ≥ 3 | λ = 0.5) = 1 − e^−0.5 (1 + 0.5 + 0.125), through the far-tail
  // series; P(X ≥ 2 | λ = 3) = 1 − 4 e^−3, through Q(k, λ).
  EXPECT_NEAR(tail_excess_test(3, 50, 0.01).p_value, 1.0 - std::exp(-0.5) * 1.625, 1e-12);
  EXPECT_NEAR(tail_excess_test(2, 300, 0.01).p_value, 1.0 - 4.0 * std::exp(-3.0), 1e-12);
  // Far beyond its expectation the count keeps a finite, ordered z.
  const TestResult far = tail_excess_test(2000, 20000, 1e-15);
  const TestResult farther = tail_excess_test(3000, 20000, 1e-15);
  EXPECT_TRUE(std::isfinite(far.z));
  EXPECT_GT(farther.z, far.z);
}

// The best of several correlations: one column is the plain test; k columns multiply the best
// p-value by k (Bonferroni), and z is that p's two-sided deviate. Under independence the
// corrected test rejects at most at its level.
TEST(StatisticalTests, BestCorrelationIsBonferroniCorrected) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  const auto noise = [&](Eigen::Index n) {
    Eigen::VectorXd v(n);
    for (auto& x : v) x = normal(rng);
    return v;
  };
  const Eigen::VectorXd x = noise(400);
  const Eigen::VectorXd y = 0.2 * x + noise(400);
  const TestResult single = correlation_test(x, y);
  const TestResult one = best_correlation_test(x, y);
  EXPECT_DOUBLE_EQ(one.statistic, single.statistic);
  EXPECT_NEAR(one.p_value, single.p_value, 1e-12 * single.p_value);
  Eigen::MatrixXd three(400, 3);
  three << noise(400), x, noise(400);
  const TestResult best = best_correlation_test(three, y);
  EXPECT_DOUBLE_EQ(best.statistic, single.statistic);
  EXPECT_NEAR(best.p_value, 3.0 * single.p_value, 1e-9 * single.p_value);
  EXPECT_NEAR(two_sided_normal_p(best.z), best.p_value, 1e-9 * best.p_value);

  int rejections = 0;
  const int trials = 2000;
  for (int trial = 0; trial < trials; ++trial) {
    Eigen::MatrixXd columns(100, 5);
    for (Eigen::Index c = 0; c < 5; ++c) columns.col(c) = noise(100);
    rejections += best_correlation_test(columns, noise(100)).p_value < 0.05;
  }
  // At most 5 %: 100 of 2000, with three standard deviations (29) of room.
  EXPECT_LE(rejections, 129);
  EXPECT_GE(rejections, 40);  // Bonferroni over independent columns is near its level
}

// The normal deviate of a log tail probability: table values, and the asymptotic regime where
// the tail itself underflows (log Q(z) ≈ −z²/2 − log(z√(2π))).
TEST(StatisticalTests, NormalDeviateOfLogP) {
  EXPECT_NEAR(normal_deviate_of_log_p(std::log(0.025)), 1.959964, 1e-5);
  EXPECT_NEAR(normal_deviate_of_log_p(std::log(1e-10)), 6.361341, 1e-5);
  EXPECT_EQ(normal_deviate_of_log_p(std::log(0.7)), 0.0);
  const double z = normal_deviate_of_log_p(-5000.0);
  EXPECT_NEAR(-0.5 * z * z - std::log(z * std::sqrt(2.0 * std::numbers::pi)), -5000.0, 1e-3);
}

// Universal inference: p = 1/T, so T = 20 sits at 5 %; no evidence is p = 1.
TEST(StatisticalTests, SplitLikelihoodRatio) {
  const TestResult at_5 = split_likelihood_ratio_test(std::log(20.0));
  EXPECT_NEAR(at_5.p_value, 0.05, 1e-12);
  EXPECT_NEAR(at_5.z, 1.644854, 1e-5);
  EXPECT_EQ(split_likelihood_ratio_test(-3.0).p_value, 1.0);
  EXPECT_GT(split_likelihood_ratio_test(2000.0).z, 60.0);
}

}  // namespace
}  // namespace tofcomp::core
