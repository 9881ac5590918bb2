#include "core/estimators.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

TEST(ErrorMoments, HandComputed) {
  const Eigen::Vector4d estimates(1.0, 3.0, 2.0, 6.0);
  const Eigen::Vector4d truth(2.0, 2.0, 2.0, 2.0);  // errors −1, 1, 0, 4
  const ErrorMoments m = error_moments(estimates, truth);
  EXPECT_EQ(m.count, 4);
  EXPECT_DOUBLE_EQ(m.mean_error, 1.0);
  EXPECT_DOUBLE_EQ(m.error_variance, (4.0 + 0.0 + 1.0 + 9.0) / 4.0);
  EXPECT_DOUBLE_EQ(m.mean_absolute_error, 1.5);
  EXPECT_DOUBLE_EQ(m.absolute_error_variance, (0.25 + 0.25 + 2.25 + 6.25) / 4.0);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt(18.0 / 4.0));
}

TEST(WindowEstimates, WindowsAndMeans) {
  const auto m = testing::mixture({-2.0, 2.0}, {0.5, 0.5}, {0.5, 0.5});
  const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(10, 0.0, 9.0);
  const Eigen::VectorXd bias = Eigen::VectorXd::Constant(10, 1.0);
  const WindowEstimates w = estimate_windows(y, bias, m, 4, 3);
  ASSERT_EQ(w.start.size(), 3u);  // windows at 0, 3, 6
  EXPECT_EQ(w.start[2], 6);
  EXPECT_DOUBLE_EQ(w.raw_mean[1], (3 + 4 + 5 + 6) / 4.0);
  EXPECT_DOUBLE_EQ(w.bias_corrected_mean[1], (3 + 4 + 5 + 6) / 4.0 - 1.0);
  EXPECT_TRUE(w.em_distance.allFinite());
}

// On data with a temperature bias and two modes, d̂ beats both ȳ and mean(y − Hθ).
TEST(WindowEstimates, EmEstimateBeatsTheMeans) {
  const auto noise = testing::mixture({-3.0, 2.0}, {1.0, 1.0}, {0.4, 0.6});
  auto bias = [](double t) { return -2.0 * (t - 24.8); };
  const auto data =
      testing::draw_measurements(testing::cycling_temperature(8000), 3000.0, bias, noise, 17);
  Eigen::VectorXd true_bias = data.true_bias;
  const WindowEstimates w = estimate_windows(data.range, true_bias, noise, 400, 50);
  const Eigen::VectorXd truth = Eigen::VectorXd::Constant(w.em_distance.size(), 3000.0);
  const double em = error_moments(w.em_distance, truth).mean_absolute_error;
  const double raw = error_moments(w.raw_mean, truth).mean_absolute_error;
  const double corrected = error_moments(w.bias_corrected_mean, truth).mean_absolute_error;
  EXPECT_LT(em, 0.5 * raw);
  EXPECT_LT(em, corrected);
}

TEST(WindowEstimates, BadInput) {
  const auto m = testing::mixture({0.0}, {1.0}, {1.0});
  EXPECT_THROW(estimate_windows(Eigen::VectorXd::Ones(5), Eigen::VectorXd::Ones(5), m, 6, 1),
               InvalidInput);
  EXPECT_THROW(estimate_windows(Eigen::VectorXd::Ones(5), Eigen::VectorXd::Ones(5), m, 0, 1),
               InvalidInput);
  EXPECT_THROW(estimate_windows(Eigen::VectorXd::Ones(5), Eigen::VectorXd::Ones(5), m, 2, 0),
               InvalidInput);
  EXPECT_THROW(error_moments(Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(3)), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
