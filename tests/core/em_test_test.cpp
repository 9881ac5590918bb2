#include "core/em_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

Eigen::VectorXd draw_mixture_ranges(const MixtureParameters& m, double d, Eigen::Index k,
                                    unsigned seed, Eigen::VectorXi* labels = nullptr) {
  const Eigen::VectorXd t = Eigen::VectorXd::Constant(k, 26.0);
  const auto data = testing::draw_measurements(
      t, d, [](double) { return 0.0; }, m, seed);
  if (labels) *labels = data.mode;
  return data.range;
}

// One mode: Eq. 23 reduces to the mean of y − Hθ − μ, reached in one step.
TEST(EmTest, OneModeIsTheCorrectedMean) {
  const auto m = testing::mixture({1.5}, {2.0}, {1.0});
  const Eigen::Vector4d y(10.0, 12.0, 9.0, 11.0);
  const Eigen::Vector4d bias(0.5, -0.5, 0.0, 1.0);
  const EmTestResult r = test_em(y, bias, m);
  EXPECT_NEAR(r.distance, (y - bias).mean() - 1.5, 1e-12);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.distance_std, 2.0 / std::sqrt(4.0), 1e-12);  // σ / √K
}

// Modes far apart: the posteriors are 0 or 1, so d̂ equals the estimate made knowing each
// sample's mode, mean(y_k − μ_{mode k}) for equal variances.
TEST(EmTest, SeparatedModesMatchTheOracle) {
  const auto m = testing::mixture({-20.0, 20.0}, {1.0, 1.0}, {0.3, 0.7});
  Eigen::VectorXi labels;
  const Eigen::VectorXd y = draw_mixture_ranges(m, 1000.0, 800, 3, &labels);
  double oracle = 0.0;
  for (Eigen::Index k = 0; k < y.size(); ++k) oracle += y[k] - m.mean[labels[k]];
  oracle /= static_cast<double>(y.size());
  const EmTestResult r = test_em(y, Eigen::VectorXd::Zero(y.size()), m);
  EXPECT_NEAR(r.distance, oracle, 1e-9);
}

// The reported standard deviation matches the spread of d̂ over independent windows.
TEST(EmTest, StandardDeviationMatchesMonteCarlo) {
  const auto m = testing::mixture({-1.5, 2.0}, {1.0, 1.2}, {0.55, 0.45});
  std::vector<double> estimates;
  double reported = 0.0;
  const int runs = 300;
  for (int run = 0; run < runs; ++run) {
    const Eigen::VectorXd y = draw_mixture_ranges(m, 500.0, 400, 100 + static_cast<unsigned>(run));
    const EmTestResult r = test_em(y, Eigen::VectorXd::Zero(y.size()), m);
    estimates.push_back(r.distance);
    reported += r.distance_std / runs;
  }
  const Eigen::Map<Eigen::VectorXd> e(estimates.data(), runs);
  const double empirical = std::sqrt((e.array() - e.mean()).square().sum() / (runs - 1));
  EXPECT_NEAR(e.mean(), 500.0, 3 * empirical / std::sqrt(runs));
  EXPECT_NEAR(reported / empirical, 1.0, 0.15);
}

// Eq. 23 as printed omits the mode offsets: its d̂ carries Σ π_i μ_i.
TEST(EmTest, PaperStepCarriesTheModeOffsets) {
  const auto m = testing::mixture({-20.0, 20.0}, {1.0, 1.0}, {0.3, 0.7});
  Eigen::VectorXi labels;
  const Eigen::VectorXd y = draw_mixture_ranges(m, 1000.0, 4000, 5, &labels);
  EmTestOptions paper;
  paper.m_step = MStep::PaperAsPrinted;
  const double fraction_mode2 = labels.cast<double>().mean();
  const double expected_offset = -20.0 * (1 - fraction_mode2) + 20.0 * fraction_mode2;
  const EmTestResult r = test_em(y, Eigen::VectorXd::Zero(y.size()), m, paper);
  EXPECT_NEAR(r.distance - 1000.0, expected_offset, 0.2);
  const EmTestResult exact = test_em(y, Eigen::VectorXd::Zero(y.size()), m);
  EXPECT_NEAR(exact.distance, 1000.0, 0.2);
}

TEST(EmTest, WarmStartAndTrace) {
  const auto m = testing::mixture({-2.0, 2.0}, {1.0, 1.0}, {0.5, 0.5});
  const Eigen::VectorXd y = draw_mixture_ranges(m, 50.0, 300, 9);
  EmTestOptions options;
  options.record_trace = true;
  const EmTestResult cold = test_em(y, Eigen::VectorXd::Zero(y.size()), m, options);
  const EmTestResult warm = test_em(y, Eigen::VectorXd::Zero(y.size()), m, options, cold.distance);
  EXPECT_NEAR(warm.distance, cold.distance, 1e-8);
  EXPECT_LE(warm.iterations, 2);
  EXPECT_EQ(static_cast<int>(cold.distance_trace.size()), cold.iterations);
}

// SQUAREM on the distance (the default): on overlapping modes, where the plain EM converges
// slowly, the same d̂ (within the tolerance) and log-likelihood in fewer M-steps, from a cold start
// and from a warm one; the responsibilities returned are those at the d returned.
TEST(EmTest, AcceleratedIterationReachesThePlainFixedPointInFewerSteps) {
  const auto m = testing::mixture({-0.8, 0.9}, {1.0, 1.2}, {0.45, 0.55});
  for (const unsigned seed : {21u, 22u, 23u}) {
    const Eigen::VectorXd y = draw_mixture_ranges(m, 3000.0, 400, seed);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(y.size());
    EmTestOptions plain;
    plain.acceleration = EmAcceleration::None;
    for (const std::optional<double> start :
         {std::optional<double>{}, std::optional<double>{2999.0}}) {
      const EmTestResult slow = test_em(y, zero, m, plain, start);
      const EmTestResult fast = test_em(y, zero, m, {}, start);
      ASSERT_TRUE(slow.converged);
      ASSERT_TRUE(fast.converged);
      EXPECT_NEAR(fast.distance, slow.distance, 1e-8) << seed;
      EXPECT_NEAR(fast.log_likelihood, slow.log_likelihood, 1e-8) << seed;
      EXPECT_LT(fast.iterations, slow.iterations) << seed;
      Eigen::MatrixXd expected;
      mixture_e_step(y.array() - fast.distance, m, expected);
      EXPECT_LE((fast.responsibilities - expected).cwiseAbs().maxCoeff(), 1e-12) << seed;
    }
  }
}

TEST(EmTest, BadInputIsNamed) {
  const auto m = testing::mixture({-2.0, 2.0}, {1.0, 1.0}, {0.5, 0.5});
  EXPECT_THROW(test_em(Eigen::VectorXd(), Eigen::VectorXd(), m), InvalidInput);
  EXPECT_THROW(test_em(Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(2), m), InvalidInput);
  Eigen::VectorXd y = Eigen::VectorXd::Ones(3);
  y[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(test_em(y, Eigen::VectorXd::Zero(3), m), InvalidInput);
  auto bad = m;
  bad.variance[0] = -1.0;
  EXPECT_THROW(test_em(Eigen::VectorXd::Ones(3), Eigen::VectorXd::Zero(3), bad), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
