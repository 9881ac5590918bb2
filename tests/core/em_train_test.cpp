#include "core/em_train.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <thread>

#include "core/basis.hpp"
#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

using testing::cubic_bias;
using testing::kSyntheticDistanceMm;

struct Trained {
  testing::SyntheticMeasurements data;
  Basis basis;
  EmTrainResult fit;
};

Trained train_on(const MixtureParameters& truth, unsigned seed, int modes, Eigen::Index samples,
                 EmTrainOptions options = {}) {
  Trained t;
  t.data = testing::draw_measurements(testing::cycling_temperature(samples), kSyntheticDistanceMm,
                                      cubic_bias, truth, seed);
  t.basis = Basis::polynomial(3, t.data.junction_temperature_c);
  options.modes = modes;
  t.fit = train_em(t.basis.design_matrix(t.data.junction_temperature_c),
                   t.data.range.array() - kSyntheticDistanceMm, options);
  return t;
}

// The fitted mean of mode i at temperature τ, H(τ)θ + μ_i, is what Eq. 8 identifies (a constant
// can move between H θ and the μ_i): compare it with the truth over the temperature range.
void expect_mode_curves_recovered(const Trained& t, const MixtureParameters& truth,
                                  double tolerance_mm) {
  const Eigen::VectorXd grid = Eigen::VectorXd::LinSpaced(9, 25.0, 28.6);
  const Eigen::VectorXd fitted_bias = t.basis.design_matrix(grid) * t.fit.theta;
  for (int i = 0; i < truth.modes(); ++i) {
    for (Eigen::Index g = 0; g < grid.size(); ++g) {
      EXPECT_NEAR(fitted_bias[g] + t.fit.mixture.mean[i], cubic_bias(grid[g]) + truth.mean[i],
                  tolerance_mm)
          << "mode " << i << " at " << grid[g] << " °C";
    }
  }
}

class EmRecoversTwoModes : public ::testing::TestWithParam<unsigned> {};

TEST_P(EmRecoversTwoModes, ParametersWithinTolerance) {
  const auto truth = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  const Trained t = train_on(truth, GetParam(), 2, 20000);
  ASSERT_TRUE(t.fit.converged);
  expect_mode_curves_recovered(t, truth, 0.15);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(std::sqrt(t.fit.mixture.variance[i]), std::sqrt(truth.variance[i]), 0.06) << i;
    EXPECT_NEAR(t.fit.mixture.weight[i], truth.weight[i], 0.02) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, EmRecoversTwoModes, ::testing::Values(1u, 2u, 3u, 4u, 5u));

class EmRecoversThreeModes : public ::testing::TestWithParam<unsigned> {};

TEST_P(EmRecoversThreeModes, ParametersWithinTolerance) {
  const auto truth = testing::mixture({-4.0, 0.0, 4.0}, {0.8, 0.8, 0.8}, {0.3, 0.45, 0.25});
  const Trained t = train_on(truth, GetParam(), 3, 30000);
  ASSERT_TRUE(t.fit.converged);
  expect_mode_curves_recovered(t, truth, 0.15);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::sqrt(t.fit.mixture.variance[i]), 0.8, 0.06) << i;
    EXPECT_NEAR(t.fit.mixture.weight[i], truth.weight[i], 0.02) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, EmRecoversThreeModes, ::testing::Values(11u, 12u, 13u));

// The exact (ECM) step maximizes over each block, so ℓ never decreases — from the default
// start and from the paper's Eq. 20 start, with two and three modes.
TEST(EmTrain, ExactStepNeverDecreasesTheLikelihood) {
  const auto two = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  const auto three = testing::mixture({-4.0, 0.0, 4.0}, {0.8, 0.8, 0.8}, {0.3, 0.45, 0.25});
  for (unsigned seed = 21; seed < 25; ++seed) {
    for (const auto init : {EmInitialization::Quantiles, EmInitialization::Paper}) {
      EmTrainOptions options;
      options.initialization = init;
      const Trained t = train_on(two, seed, 2, 4000, options);
      ASSERT_GE(t.fit.trace.size(), 2u);
      for (std::size_t i = 1; i < t.fit.trace.size(); ++i) {
        EXPECT_GE(t.fit.trace[i].log_likelihood, t.fit.trace[i - 1].log_likelihood -
                                                     1e-9 * std::abs(t.fit.trace[i].log_likelihood))
            << "seed " << seed << " iteration " << i;
      }
    }
    const Trained t3 = train_on(three, seed, 3, 6000);
    for (std::size_t i = 1; i < t3.fit.trace.size(); ++i) {
      EXPECT_GE(
          t3.fit.trace[i].log_likelihood,
          t3.fit.trace[i - 1].log_likelihood - 1e-9 * std::abs(t3.fit.trace[i].log_likelihood));
    }
  }
}

// Eq. 19 as printed is not a maximization step: its fixed point has a lower likelihood than
// the exact step's, and its σ² is a second moment that includes μ².
TEST(EmTrain, PaperStepAsPrintedReachesALowerLikelihood) {
  const auto truth = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  EmTrainOptions paper;
  paper.m_step = MStep::PaperAsPrinted;
  paper.max_iterations = 300;
  for (unsigned seed = 31; seed < 34; ++seed) {
    const Trained exact = train_on(truth, seed, 2, 5000);
    const Trained printed = train_on(truth, seed, 2, 5000, paper);
    EXPECT_GT(exact.fit.log_likelihood, printed.fit.log_likelihood + 1.0) << seed;
    for (int i = 0; i < 2; ++i) {
      EXPECT_GE(printed.fit.mixture.variance[i],
                printed.fit.mixture.mean[i] * printed.fit.mixture.mean[i]);
    }
  }
}

TEST(EmTrain, ResponsibilitiesIdentifyTheModes) {
  const auto truth = testing::mixture({-5.0, 5.0}, {1.0, 1.0}, {0.5, 0.5});
  const Trained t = train_on(truth, 41, 2, 4000);
  int agree = 0;
  for (Eigen::Index k = 0; k < t.data.mode.size(); ++k) {
    const int guess = t.fit.responsibilities(k, 1) > 0.5 ? 1 : 0;
    agree += guess == t.data.mode[k];
  }
  EXPECT_GT(agree, 0.99 * t.data.mode.size());
}

class EmTrainBadInput : public ::testing::Test {
 protected:
  Eigen::VectorXd t = testing::cycling_temperature(500);
  Eigen::MatrixXd h = Basis::polynomial(2, t).design_matrix(t);
  Eigen::VectorXd y = testing::draw_measurements(t, 0.0, cubic_bias,
                                                 testing::mixture({-2, 2}, {1, 1}, {0.5, 0.5}), 7)
                          .range;
};

TEST_F(EmTrainBadInput, NaNIsNamed) {
  y[17] = std::numeric_limits<double>::quiet_NaN();
  try {
    train_em(h, y);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("[17]"), std::string::npos) << e.what();
  }
  y[17] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(train_em(h, y), InvalidInput);
}

TEST_F(EmTrainBadInput, MismatchedLengths) {
  EXPECT_THROW(train_em(h, y.head(400)), InvalidInput);
}

TEST_F(EmTrainBadInput, TooFewSamplesForTheBasis) {
  EXPECT_THROW(train_em(h.topRows(7), y.head(7)), InvalidInput);
}

TEST_F(EmTrainBadInput, ZeroVariance) {
  EXPECT_THROW(train_em(h, Eigen::VectorXd::Constant(y.size(), 4.0)), NumericalError);
}

// End of §5: HᵀC⁻¹H needs N distinct temperatures for N columns.
TEST_F(EmTrainBadInput, TooFewDistinctTemperaturesIsSingular) {
  Eigen::VectorXd two_temperatures(500);
  for (Eigen::Index k = 0; k < 500; ++k) two_temperatures[k] = k % 2 ? 25.0 : 27.0;
  const Eigen::MatrixXd h4 = Basis::polynomial(4, two_temperatures).design_matrix(two_temperatures);
  EXPECT_THROW(train_em(h4, y), NumericalError);
}

// With the paper's start (μ = ±0.1) on ranges 10 units above d, every sample goes to mode 1
// and mode 2 is left empty: a clear error, not a NaN.
TEST_F(EmTrainBadInput, EverySampleInOneModeIsAnError) {
  EmTrainOptions options;
  options.initialization = EmInitialization::Paper;
  const Eigen::VectorXd shifted = (y.array() - y.mean() + 10.0) / 10.0 + 10.0;
  try {
    train_em(h, shifted, options);
    FAIL();
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("mode 2"), std::string::npos) << e.what();
  }
}

TEST_F(EmTrainBadInput, OptionsAreChecked) {
  EmTrainOptions options;
  options.modes = 0;
  EXPECT_THROW(train_em(h, y, options), InvalidInput);
  options.modes = 3;
  options.initialization = EmInitialization::Paper;
  EXPECT_THROW(train_em(h, y, options), InvalidInput);
}

// A warm start at a converged fit stays there: the next EM steps barely move it.
TEST(EmTrain, AWarmStartAtTheMaximumStaysThere) {
  const auto truth = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  const Trained cold = train_on(truth, 21, 2, 20000);
  EmTrainOptions options;
  options.start = EmStartingPoint{cold.fit.theta, cold.fit.mixture};
  const Trained warm = train_on(truth, 21, 2, 20000, options);
  EXPECT_TRUE(warm.fit.converged);
  EXPECT_LE(warm.fit.iterations, 3);
  EXPECT_LT(cold.fit.iterations, 1000);
  EXPECT_NEAR(warm.fit.log_likelihood, cold.fit.log_likelihood, 1e-6 * 20000);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(warm.fit.mixture.mean[i], cold.fit.mixture.mean[i], 1e-3);
}

// A start from a smaller nested basis: θ is padded with zeros, and the fit reaches the same
// maximum as a cold start of the larger basis.
TEST(EmTrain, AStartFromANestedBasisReachesTheSameMaximum) {
  const auto truth = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  const auto data = testing::draw_measurements(testing::cycling_temperature(20000),
                                               kSyntheticDistanceMm, cubic_bias, truth, 23);
  const Eigen::VectorXd y = data.range.array() - kSyntheticDistanceMm;
  const Basis two = Basis::polynomial(2, data.junction_temperature_c);
  const Basis three = Basis::polynomial(3, data.junction_temperature_c);
  const EmTrainResult small = train_em(two.design_matrix(data.junction_temperature_c), y);
  EmTrainOptions options;
  options.start = EmStartingPoint{small.theta, small.mixture};
  const Eigen::MatrixXd h3 = three.design_matrix(data.junction_temperature_c);
  const EmTrainResult warm = train_em(h3, y, options);
  const EmTrainResult cold = train_em(h3, y);
  EXPECT_NEAR(warm.log_likelihood, cold.log_likelihood, 1e-6 * 20000);
  for (Eigen::Index j = 0; j < 3; ++j) EXPECT_NEAR(warm.theta[j], cold.theta[j], 1e-3);
}

// The sweeps' stripes handed to threads (here two, each taking the stripes in reverse order)
// give the fit of the serial run bit for bit: each stripe's sums start from zero and the
// stripes are added in order whatever ran them (core/mixture_sweep.hpp).
TEST(EmTrain, StripesOnThreadsGiveTheSerialFitBitForBit) {
  EmTrainOptions threaded;
  threaded.parallel_for = [](int count, const std::function<void(int)>& task) {
    std::thread other([&] {
      for (int i = count - 1; i >= 0; i -= 2) task(i);
    });
    for (int i = count - 2; i >= 0; i -= 2) task(i);
    other.join();
  };
  const auto truth = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  const Trained serial = train_on(truth, 7, 2, 50000);  // a dozen stripes, the last one short
  const Trained parallel = train_on(truth, 7, 2, 50000, threaded);
  ASSERT_TRUE(serial.fit.converged);
  EXPECT_EQ(parallel.fit.iterations, serial.fit.iterations);
  EXPECT_EQ(parallel.fit.log_likelihood, serial.fit.log_likelihood);
  EXPECT_EQ(parallel.fit.theta, serial.fit.theta);
  EXPECT_EQ(parallel.fit.mixture.mean, serial.fit.mixture.mean);
  EXPECT_EQ(parallel.fit.mixture.variance, serial.fit.mixture.variance);
  EXPECT_EQ(parallel.fit.mixture.weight, serial.fit.mixture.weight);
  EXPECT_EQ(parallel.fit.responsibilities, serial.fit.responsibilities);
}

TEST(EmTrain, AStartThatDoesNotFitIsRefused) {
  const auto truth = testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4});
  const auto data = testing::draw_measurements(testing::cycling_temperature(2000),
                                               kSyntheticDistanceMm, cubic_bias, truth, 25);
  const Eigen::VectorXd y = data.range.array() - kSyntheticDistanceMm;
  const Eigen::MatrixXd h =
      Basis::polynomial(2, data.junction_temperature_c).design_matrix(data.junction_temperature_c);
  EmTrainOptions options;
  options.start = EmStartingPoint{Eigen::VectorXd::Zero(3), truth};  // θ longer than H is wide
  EXPECT_THROW(train_em(h, y, options), InvalidInput);
  options.start = EmStartingPoint{Eigen::VectorXd::Zero(2), truth};
  options.modes = 3;  // the mixture has two
  EXPECT_THROW(train_em(h, y, options), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
