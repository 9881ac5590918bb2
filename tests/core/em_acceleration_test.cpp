// SQUAREM in EM training (core/squarem.hpp, core/em_train.hpp): it must reach the fixed point
// of the plain exact EM (the same log-likelihood and parameters, and a zero score there), in far
// fewer EM steps, with the log-likelihood never decreasing along the points it moves to; and the
// paper's M-step as printed, which is not a maximization, must stay plain EM.
#include <gtest/gtest.h>

#include <cmath>

#include "core/basis.hpp"
#include "core/em_train.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

using testing::kSyntheticDistanceMm;
// Tight enough that both iterations stand at the fixed point to well below the tolerances the
// comparisons use.
constexpr double kTightLikelihoodTolerance = 1e-14;
constexpr double kTightWeightTolerance = 1e-10;
constexpr int kPlainIterationCap = 50000;

struct Case {
  const char* name;
  MixtureParameters truth;
  Eigen::Index samples;
  unsigned seed;
  double fewer_steps;  // plain EM's M-steps over SQUAREM's, at least
};

// Well separated, overlapping (the modes a standard deviation or two apart: slow EM) and three
// overlapping modes with unequal spreads.
std::vector<Case> cases() {
  return {
      // Plain EM is quick here already (tens of steps).
      {"separated", testing::mixture({-2.0, 3.0}, {1.0, 1.5}, {0.6, 0.4}), 8000, 51, 1.4},
      {"overlapping", testing::mixture({-0.8, 0.9}, {0.7, 1.0}, {0.55, 0.45}), 8000, 52, 5.0},
      {"three overlapping", testing::mixture({-1.5, 0.0, 1.6}, {0.6, 0.8, 0.7}, {0.3, 0.4, 0.3}),
       12000, 53, 5.0},
  };
}

struct Problem {
  Eigen::MatrixXd h;
  Eigen::VectorXd y;
};

Problem problem(const Case& c) {
  const auto data =
      testing::draw_measurements(testing::cycling_temperature(c.samples), kSyntheticDistanceMm,
                                 testing::cubic_bias, c.truth, c.seed);
  return {
      Basis::polynomial(3, data.junction_temperature_c).design_matrix(data.junction_temperature_c),
      data.range.array() - kSyntheticDistanceMm};
}

EmTrainResult fit(const Problem& p, int modes, EmAcceleration acceleration,
                  MStep m_step = MStep::Exact) {
  EmTrainOptions options;
  options.modes = modes;
  options.m_step = m_step;
  options.acceleration = acceleration;
  options.log_likelihood_tolerance = kTightLikelihoodTolerance;
  options.weight_tolerance = kTightWeightTolerance;
  options.max_iterations = kPlainIterationCap;
  return train_em(p.h, p.y, options);
}

TEST(EmAcceleration, ReachesThePlainFixedPointInFarFewerSteps) {
  for (const Case& c : cases()) {
    const Problem p = problem(c);
    const int modes = c.truth.modes();
    const EmTrainResult plain = fit(p, modes, EmAcceleration::None);
    const EmTrainResult fast = fit(p, modes, EmAcceleration::Squarem);
    ASSERT_TRUE(plain.converged) << c.name;
    ASSERT_TRUE(fast.converged) << c.name;
    EXPECT_NEAR(fast.log_likelihood, plain.log_likelihood, 1e-7 * static_cast<double>(c.samples))
        << c.name;
    for (Eigen::Index j = 0; j < p.h.cols(); ++j) {
      EXPECT_NEAR(fast.theta[j], plain.theta[j], 1e-4) << c.name << " theta " << j;
    }
    for (int i = 0; i < modes; ++i) {
      EXPECT_NEAR(fast.mixture.mean[i], plain.mixture.mean[i], 1e-4) << c.name << " mode " << i;
      EXPECT_NEAR(fast.mixture.variance[i], plain.mixture.variance[i], 1e-4) << c.name;
      EXPECT_NEAR(fast.mixture.weight[i], plain.mixture.weight[i], 1e-5) << c.name;
    }
    // Far fewer applications of the EM map where plain EM is slow (overlapping modes), and
    // fewer E-steps, the extrapolated points tried included.
    EXPECT_GE(plain.iterations, c.fewer_steps * fast.iterations)
        << c.name << ": plain " << plain.iterations << ", SQUAREM " << fast.iterations;
    EXPECT_GE(plain.likelihood_evaluations, c.fewer_steps * fast.likelihood_evaluations)
        << c.name << ": plain " << plain.likelihood_evaluations << ", SQUAREM "
        << fast.likelihood_evaluations;
  }
}

// At the accelerated fit the score vanishes: the log-likelihood's central differences in every
// coordinate of θ and μ are zero to the differences' own error.
TEST(EmAcceleration, TheScoreVanishesAtTheAcceleratedFit) {
  const Case c = cases()[1];
  const Problem p = problem(c);
  const EmTrainResult fast = fit(p, 2, EmAcceleration::Squarem);
  ASSERT_TRUE(fast.converged);
  const auto log_likelihood = [&](const Eigen::VectorXd& theta, const MixtureParameters& m) {
    return mixture_log_likelihood(p.y - p.h * theta, m);
  };
  constexpr double kStep = 1e-5;
  // A coordinate's score at a point displaced by one unit from the maximum is of the order of
  // the observed information, ~K; at the maximum it is this much smaller.
  const double tolerance = 1e-4 * static_cast<double>(c.samples);
  for (Eigen::Index j = 0; j < p.h.cols(); ++j) {
    Eigen::VectorXd up = fast.theta, down = fast.theta;
    up[j] += kStep;
    down[j] -= kStep;
    const double score =
        (log_likelihood(up, fast.mixture) - log_likelihood(down, fast.mixture)) / (2.0 * kStep);
    EXPECT_NEAR(score, 0.0, tolerance) << "theta " << j;
  }
  for (int i = 0; i < 2; ++i) {
    MixtureParameters up = fast.mixture, down = fast.mixture;
    up.mean[i] += kStep;
    down.mean[i] -= kStep;
    const double score =
        (log_likelihood(fast.theta, up) - log_likelihood(fast.theta, down)) / (2.0 * kStep);
    EXPECT_NEAR(score, 0.0, tolerance) << "mu " << i;
    up = fast.mixture, down = fast.mixture;
    up.variance[i] += kStep;
    down.variance[i] -= kStep;
    const double variance_score =
        (log_likelihood(fast.theta, up) - log_likelihood(fast.theta, down)) / (2.0 * kStep);
    EXPECT_NEAR(variance_score, 0.0, tolerance) << "sigma2 " << i;
  }
}

TEST(EmAcceleration, TheLikelihoodNeverDecreasesAlongTheAcceptedPoints) {
  for (const Case& c : cases()) {
    const Problem p = problem(c);
    for (const EmInitialization init : {EmInitialization::Quantiles, EmInitialization::Paper}) {
      if (init == EmInitialization::Paper && c.truth.modes() != 2) continue;
      EmTrainOptions options;
      options.modes = c.truth.modes();
      options.initialization = init;
      const EmTrainResult fast = train_em(p.h, p.y, options);
      ASSERT_GE(fast.trace.size(), 3u) << c.name;
      for (std::size_t i = 1; i < fast.trace.size(); ++i) {
        EXPECT_GE(fast.trace[i].log_likelihood,
                  fast.trace[i - 1].log_likelihood - 1e-12 * std::abs(fast.trace[i].log_likelihood))
            << c.name << " point " << i;
      }
      EXPECT_EQ(fast.trace.back().log_likelihood, fast.log_likelihood) << c.name;
    }
  }
}

// Eq. 19 as printed is not a maximization step: the acceleration leaves it alone.
TEST(EmAcceleration, ThePapersStepAsPrintedStaysPlainEm) {
  const Problem p = problem(cases()[0]);
  EmTrainOptions options;
  options.m_step = MStep::PaperAsPrinted;
  options.max_iterations = 300;
  options.acceleration = EmAcceleration::Squarem;
  const EmTrainResult asked = train_em(p.h, p.y, options);
  options.acceleration = EmAcceleration::None;
  const EmTrainResult plain = train_em(p.h, p.y, options);
  EXPECT_EQ(asked.iterations, plain.iterations);
  EXPECT_EQ(asked.likelihood_evaluations, asked.iterations + 1);
  EXPECT_EQ(asked.log_likelihood, plain.log_likelihood);
  EXPECT_EQ(asked.theta, plain.theta);
  EXPECT_EQ(asked.mixture.weight, plain.mixture.weight);
}

}  // namespace
}  // namespace tofcomp::core
