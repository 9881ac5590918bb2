#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/change_detector.hpp"
#include "core/error.hpp"
#include "core/sliding_window_estimator.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

const MixtureParameters kModes = testing::mixture({-2.0, 2.5}, {0.9, 1.1}, {0.55, 0.45});

Eigen::VectorXd draw(double d, Eigen::Index k, unsigned seed) {
  return testing::draw_measurements(
             Eigen::VectorXd::Constant(k, 26.0), d, [](double) { return 0.0; }, kModes, seed)
      .range;
}

// CUSUM by hand with one standard mode: z = e, drift 0.5, threshold 2.
TEST(ChangeDetector, CusumByHand) {
  ChangeDetector cusum({0.5, 2.0});
  const auto one = testing::mixture({0.0}, {1.0}, {1.0});
  EXPECT_FALSE(cusum.update(1.0, one));  // g+ = 0.5
  EXPECT_DOUBLE_EQ(cusum.upper(), 0.5);
  EXPECT_FALSE(cusum.update(-0.2, one));  // g+ = max(0, 0.5 − 0.7) = 0, g− = 0
  EXPECT_DOUBLE_EQ(cusum.upper(), 0.0);
  EXPECT_FALSE(cusum.update(1.5, one));  // g+ = 1.0
  EXPECT_TRUE(cusum.update(1.6, one));   // g+ = 2.1 > 2: alarm, restart
  EXPECT_DOUBLE_EQ(cusum.upper(), 0.0);
  EXPECT_FALSE(cusum.update(-2.0, one));  // g− = 1.5
  EXPECT_DOUBLE_EQ(cusum.lower(), 1.5);
  EXPECT_THROW(cusum.update(NAN, one), InvalidInput);
}

// At every range the window's d̂ is the batch EM test of the latest W ranges.
TEST(SlidingWindow, EqualsBatchTestOnTheLatestWindow) {
  SlidingWindowOptions options;
  options.window = 100;
  SlidingWindowEstimator estimator(kModes, options);
  const Eigen::VectorXd y = draw(3000.0, 400, 3);
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    const WindowEstimate e = estimator.add(y[k]);
    ASSERT_FALSE(e.change_detected) << k;
    if (k % 37 != 0 && k != y.size() - 1) continue;
    const Eigen::Index n = std::min<Eigen::Index>(k + 1, 100);
    const auto batch = test_em(y.segment(k + 1 - n, n), Eigen::VectorXd::Zero(n), kModes);
    EXPECT_NEAR(e.distance, batch.distance, 1e-4) << k;
    EXPECT_EQ(e.samples, n);
  }
}

SlidingWindowOptions incremental(Eigen::Index window = 200) {
  SlidingWindowOptions options;
  options.window = window;
  options.method = WindowEm::Incremental;
  return options;
}

// Incremental EM tracks the batch EM test of the latest W ranges. Its responsibilities are up
// to W / refreshes ranges old, so its d̂ differs from the batch d̂ by a fraction of d̂'s own
// standard deviation σ_d: checked at 1,000 points over a million ranges (5,000 windows, so
// also that the running sums do not drift), for the paper's well separated modes and for modes
// that overlap (responsibilities then depend strongly on d). The root mean square difference
// stays under 0.15 σ_d, which adds at most 2.3 % to d̂'s variance; the largest under 0.6 σ_d.
TEST(SlidingWindow, IncrementalTracksTheBatchEstimate) {
  const MixtureParameters overlapping = testing::mixture({-0.5, 0.6}, {1.0, 1.2}, {0.5, 0.5});
  for (const MixtureParameters& modes : {kModes, overlapping}) {
    SlidingWindowEstimator estimator(modes, incremental(200));
    const Eigen::Index n = 1000000;
    const Eigen::VectorXd y =
        testing::draw_measurements(
            Eigen::VectorXd::Constant(n, 26.0), 3000.0, [](double) { return 0.0; }, modes, 17)
            .range;
    WindowEstimate e;
    double sum_square = 0.0;
    double largest = 0.0;
    int checks = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
      e = estimator.add(y[k]);
      ASSERT_FALSE(e.change_detected) << k;
      if ((k + 1) % 1000 != 0) continue;
      const auto batch = test_em(y.segment(k + 1 - 200, 200), Eigen::VectorXd::Zero(200), modes);
      const double z = (e.distance - batch.distance) / batch.distance_std;
      sum_square += z * z;
      largest = std::max(largest, std::abs(z));
      ++checks;
      EXPECT_NEAR(e.distance_std, batch.distance_std, 0.1 * batch.distance_std) << k;
      EXPECT_EQ(e.samples, 200);
    }
    std::printf("incremental vs batch: rms %.4f, largest %.4f (in sigma_d)\n",
                std::sqrt(sum_square / checks), largest);
    EXPECT_LT(std::sqrt(sum_square / checks), 0.15);
    EXPECT_LT(largest, 0.6);
    // This range's posterior is Eq. 22 at the window's d̂.
    Eigen::MatrixXd r;
    mixture_e_step(Eigen::VectorXd::Constant(1, y[n - 1] - e.distance), modes, r);
    EXPECT_NEAR((e.posterior - r.row(0).transpose()).cwiseAbs().maxCoeff(), 0.0, 1e-12);
    Eigen::Index best = 0;
    r.row(0).maxCoeff(&best);
    EXPECT_EQ(e.most_probable_mode, best);
  }
}

// An object 300 mm in front of the wall: the window restarts within a few ranges and then
// estimates the object, not an average of both.
TEST(SlidingWindow, RestartsWhenTheSceneChanges) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    SlidingWindowEstimator estimator(kModes, seed <= 5 ? SlidingWindowOptions{} : incremental());
    const Eigen::VectorXd wall = draw(3000.0, 2000, seed);
    const Eigen::VectorXd object = draw(2700.0, 400, seed + 100);
    int false_alarms = 0;
    for (Eigen::Index k = 0; k < wall.size(); ++k)
      false_alarms += estimator.add(wall[k]).change_detected;
    EXPECT_EQ(false_alarms, 0) << seed;
    Eigen::Index detected_after = -1;
    WindowEstimate last;
    for (Eigen::Index k = 0; k < object.size(); ++k) {
      last = estimator.add(object[k]);
      if (last.change_detected && detected_after < 0) detected_after = k;
    }
    EXPECT_GE(detected_after, 0) << seed;
    EXPECT_LE(detected_after, 3) << seed;
    EXPECT_NEAR(last.distance, 2700.0, 0.5) << seed;
    EXPECT_FALSE(last.restarting);
  }
}

TEST(SlidingWindow, RestartingFlagUntilMinSamples) {
  SlidingWindowOptions options;
  options.min_samples = 5;
  SlidingWindowEstimator estimator(kModes, options);
  const Eigen::VectorXd y = draw(1000.0, 6, 9);
  for (Eigen::Index k = 0; k < 6; ++k) EXPECT_EQ(estimator.add(y[k]).restarting, k < 4) << k;
  EXPECT_THROW(estimator.add(INFINITY), InvalidInput);
  options.min_samples = 0;
  EXPECT_THROW(SlidingWindowEstimator(kModes, options), InvalidInput);
  options.min_samples = 5;
  options.refreshes = -1;
  EXPECT_THROW(SlidingWindowEstimator(kModes, options), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
