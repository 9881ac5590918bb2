// The max-T calibration against what is known without it: the one-sided Student quantile for a
// single candidate, Šidák's level for independent ones, the same law for copies of one candidate,
// and the family-wise level on data with nothing in them.
#include "core/sign_flip_max_t.hpp"

#include <gtest/gtest.h>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <random>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

constexpr double kAlpha = 0.05;

Eigen::MatrixXd normal_blocks(Eigen::Index blocks, Eigen::Index candidates, double shared,
                              std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd g(blocks, candidates);
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const double common = normal(rng);
    for (Eigen::Index j = 0; j < candidates; ++j) {
      g(b, j) = std::sqrt(shared) * common + std::sqrt(1.0 - shared) * normal(rng);
    }
  }
  return g;
}

// One candidate's own test against closed forms: gains 1, 2, 3 have mean 2 and sd 1, so
// t = 2√3; with two degrees of freedom P(T ≥ t) = (1 − t / √(t² + 2)) / 2.
TEST(BlockGainTTest, MatchesStudentsClosedForm) {
  const Eigen::Vector3d gains(1.0, 2.0, 3.0);
  const BlockGainTest test = block_gain_t_test(gains);
  const double t = 2.0 * std::sqrt(3.0);
  EXPECT_NEAR(test.t, t, 1e-12);
  EXPECT_NEAR(test.p, 0.5 * (1.0 - t / std::sqrt(t * t + 2.0)), 1e-12);
  // A gain on no block, or one: nothing to test.
  const BlockGainTest none = block_gain_t_test(Eigen::VectorXd::Constant(1, 5.0));
  EXPECT_EQ(none.t, 0.0);
  EXPECT_EQ(none.p, 1.0);
  // Equal gains on every block (a candidate identical to another): t 0, p one half.
  const BlockGainTest same = block_gain_t_test(Eigen::VectorXd::Zero(10));
  EXPECT_EQ(same.t, 0.0);
  EXPECT_NEAR(same.p, 0.5, 1e-12);
}

TEST(SignFlipMaxT, OneCandidateGivesStudentsQuantile) {
  std::mt19937_64 rng(1);
  const Eigen::MatrixXd g = normal_blocks(200, 1, 0.0, rng);
  const SignFlipMaxT calibration(g);
  const double expected = boost::math::quantile(
      boost::math::complement(boost::math::students_t(199.0), kAlpha));
  // 9,999 draws: the 5 % point is known to about ±0.03 in t.
  EXPECT_NEAR(calibration.critical_t(kAlpha), expected, 0.1);
}

TEST(SignFlipMaxT, IndependentCandidatesGiveSidaksLevel) {
  std::mt19937_64 rng(2);
  constexpr int kCandidates = 20;
  const Eigen::MatrixXd g = normal_blocks(300, kCandidates, 0.0, rng);
  const SignFlipMaxT calibration(g);
  const double per_candidate = 1.0 - std::pow(1.0 - kAlpha, 1.0 / kCandidates);
  const double sidak = boost::math::quantile(
      boost::math::complement(boost::math::normal(), per_candidate));
  EXPECT_NEAR(calibration.critical_t(kAlpha), sidak, 0.15);
}

TEST(SignFlipMaxT, CopiesOfOneCandidateCostNothing) {
  std::mt19937_64 rng(3);
  const Eigen::MatrixXd one = normal_blocks(150, 1, 0.0, rng);
  Eigen::MatrixXd copies(150, 12);
  // Scaled by powers of two, so that every draw's t is the same to the last bit.
  for (Eigen::Index j = 0; j < copies.cols(); ++j) {
    copies.col(j) = std::ldexp(1.0, static_cast<int>(j)) * one.col(0);
  }
  const SignFlipMaxT single(one), many(copies);
  // A scaled copy has the same t in every draw: the same law, draw for draw.
  EXPECT_DOUBLE_EQ(many.critical_t(kAlpha), single.critical_t(kAlpha));
  const double t = SignFlipMaxT::t_statistic(one.col(0));
  EXPECT_DOUBLE_EQ(many.adjusted_p(t), single.adjusted_p(t));
}

TEST(SignFlipMaxT, HoldsTheFamilyWiseLevelAndBeatsBonferroniOnRelatedCandidates) {
  std::mt19937_64 rng(4);
  constexpr int kSets = 400;
  constexpr int kCandidates = 10;
  constexpr Eigen::Index kBlocks = 60;
  constexpr int kDraws = 999;
  const double bonferroni = boost::math::quantile(boost::math::complement(
      boost::math::students_t(kBlocks - 1.0), kAlpha / kCandidates));
  int alarms = 0, bonferroni_alarms = 0;
  double critical_sum = 0.0;
  for (int set = 0; set < kSets; ++set) {
    // Candidates that share most of their blocks' noise, as terms on one covariate do.
    const Eigen::MatrixXd g = normal_blocks(kBlocks, kCandidates, 0.8, rng);
    const SignFlipMaxT calibration(g, kDraws);
    double largest = -1e300;
    for (Eigen::Index j = 0; j < g.cols(); ++j) {
      largest = std::max(largest, SignFlipMaxT::t_statistic(g.col(j)));
    }
    const double critical = calibration.critical_t(kAlpha);
    critical_sum += critical;
    alarms += largest > critical ? 1 : 0;
    bonferroni_alarms += largest > bonferroni ? 1 : 0;
  }
  // Binomial(400, 0.05): mean 20, sd 4.4.
  EXPECT_GE(alarms, 8);
  EXPECT_LE(alarms, 34);
  EXPECT_LT(bonferroni_alarms, alarms);
  EXPECT_LT(critical_sum / kSets, bonferroni - 0.2);
}

TEST(SignFlipMaxT, AdjustedPAndCriticalTAgree) {
  std::mt19937_64 rng(5);
  const SignFlipMaxT calibration(normal_blocks(80, 6, 0.5, rng), 999);
  const double critical = calibration.critical_t(kAlpha);
  EXPECT_LE(calibration.adjusted_p(std::nextafter(critical, 1e300)), kAlpha);
  EXPECT_GT(calibration.adjusted_p(critical), kAlpha);
  EXPECT_LE(calibration.adjusted_p(10.0), calibration.adjusted_p(1.0));
  EXPECT_DOUBLE_EQ(calibration.adjusted_p(-1e300), 1.0);
  EXPECT_EQ(calibration.critical_t(1e-6), std::numeric_limits<double>::infinity());
}

TEST(SignFlipMaxT, ColumnsThatDoNotVaryAreLeftOut) {
  std::mt19937_64 rng(6);
  Eigen::MatrixXd g = normal_blocks(100, 2, 0.0, rng);
  const SignFlipMaxT alone(g.col(0));
  g.col(1).setConstant(0.25);
  const SignFlipMaxT with_constant(g);
  EXPECT_DOUBLE_EQ(with_constant.critical_t(kAlpha), alone.critical_t(kAlpha));
  const SignFlipMaxT none(Eigen::MatrixXd::Constant(30, 3, 1.0));
  EXPECT_DOUBLE_EQ(none.adjusted_p(1e6), 1.0);
}

TEST(SignFlipMaxT, RefusesWhatCannotBeCalibrated) {
  EXPECT_THROW(SignFlipMaxT(Eigen::MatrixXd::Ones(1, 3)), InvalidInput);
  EXPECT_THROW(SignFlipMaxT(Eigen::MatrixXd(5, 0)), InvalidInput);
  Eigen::MatrixXd g = Eigen::MatrixXd::Random(10, 2);
  g(4, 1) = std::nan("");
  try {
    SignFlipMaxT{g};
    FAIL() << "a NaN was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("block values"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::core
