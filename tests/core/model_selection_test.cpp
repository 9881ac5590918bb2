#include "core/model_selection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

std::vector<Basis> polynomial_candidates(const Eigen::VectorXd& t, int max_order) {
  std::vector<Basis> out;
  for (int n = 1; n <= max_order; ++n) out.push_back(Basis::polynomial(n, t));
  return out;
}

TEST(ModelSelection, NullLikelihoodIsTheGaussianClosedForm) {
  const Eigen::Vector4d v(1.0, 2.0, 3.0, 6.0);  // mean 3, variance 3.5
  EXPECT_NEAR(single_gaussian_log_likelihood(v),
              -2.0 * (std::log(2 * std::numbers::pi * 3.5) + 1.0), 1e-12);
}

TEST(ModelSelection, Equation25AsPrintedByHand) {
  const auto m = testing::mixture({0.0, 1.0}, {1.0, 2.0}, {0.5, 0.5});
  const Eigen::Vector2d e(0.5, 2.0);
  Eigen::MatrixXd r(2, 2);
  r << 0.75, 0.25, 0.1, 0.9;
  const double expected = std::log(1.0) * 0.85 + std::log(4.0) * 1.15 +
                          (0.75 * 0.25 + 0.1 * 4.0) / 2.0 + (0.25 * 0.25 + 0.9 * 1.0) / 8.0;
  EXPECT_NEAR(paper_eq25_statistic(e, r, m), expected, 1e-12);
}

// A cubic bias of a few mm on bimodal noise: BIC picks order 3. The held-out likelihood, like
// AIC, is not consistent: it never under-fits here but may take one order more.
TEST(ModelSelection, PicksTheTrueOrder) {
  const auto noise = testing::mixture({-2.0, 2.0}, {0.8, 0.8}, {0.5, 0.5});
  auto bias = [](double t) {
    const double z = (t - 26.8) / 2.0;
    return 3.0 * z + 2.0 * (1.5 * z * z - 0.5) + 2.5 * (2.5 * z * z * z - 1.5 * z);
  };
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const auto data =
        testing::draw_measurements(testing::cycling_temperature(6000), 0.0, bias, noise, seed);
    const auto result = select_model(polynomial_candidates(data.junction_temperature_c, 7),
                                     data.junction_temperature_c, data.range);
    ASSERT_EQ(result.scores.size(), 7u);
    EXPECT_EQ(result.best_by_bic, 2) << "seed " << seed;  // order 3
    EXPECT_GE(result.best_by_held_out, 2) << "seed " << seed;
    EXPECT_LE(result.best_by_held_out, 3) << "seed " << seed;
    EXPECT_GT(result.scores[2].glr, result.scores[1].glr + 100.0);
  }
}

// No temperature effect at all: BIC keeps the smallest basis and the held-out likelihood
// does not reward the largest; the in-sample GLR, by contrast, grows with the order.
TEST(ModelSelection, PureNoiseDoesNotPickTheLargestOrder) {
  const auto noise = testing::mixture({-2.0, 2.0}, {0.8, 0.8}, {0.5, 0.5});
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const auto data = testing::draw_measurements(
        testing::cycling_temperature(4000), 0.0, [](double) { return 0.0; }, noise, seed);
    const auto result = select_model(polynomial_candidates(data.junction_temperature_c, 8),
                                     data.junction_temperature_c, data.range);
    EXPECT_EQ(result.best_by_bic, 0) << "seed " << seed;
    EXPECT_NE(result.best_by_held_out, 7) << "seed " << seed;
    EXPECT_GE(result.scores[7].log_likelihood, result.scores[0].log_likelihood - 1e-6);
  }
}

// A candidate that cannot be trained is reported with its error; the others still are scored.
TEST(ModelSelection, UntrainableCandidateIsReportedNotFatal) {
  Eigen::VectorXd t(800);
  for (Eigen::Index k = 0; k < t.size(); ++k) t[k] = 25.0 + (k % 3);  // three temperatures
  const auto data = testing::draw_measurements(
      t, 0.0, [](double x) { return 0.5 * x; }, testing::mixture({-2, 2}, {1, 1}, {0.5, 0.5}), 3);
  const auto result =
      select_model({Basis::polynomial(1, t), Basis::polynomial(5, t)}, t, data.range);
  EXPECT_TRUE(result.scores[0].ok);
  EXPECT_FALSE(result.scores[1].ok);
  EXPECT_NE(result.scores[1].error.find("singular"), std::string::npos) << result.scores[1].error;
  EXPECT_EQ(result.best_by_bic, 0);
}

TEST(ModelSelection, BadInput) {
  const Eigen::VectorXd t = testing::cycling_temperature(1000);
  EXPECT_THROW(select_model({}, t, t), InvalidInput);
  EXPECT_THROW(select_model({Basis::polynomial(1, t)}, t, t.head(10)), InvalidInput);
  EXPECT_THROW(select_model({Basis::polynomial(1, t)}, t.head(100), t.head(100)), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
