#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/change_detector.hpp"
#include "core/covariate_table.hpp"
#include "core/error.hpp"
#include "core/extended_em.hpp"
#include "core/sliding_window_estimator.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

const MixtureParameters kModes = testing::mixture({-2.0, 2.5}, {0.9, 1.1}, {0.55, 0.45});

Eigen::VectorXd draw_window_ranges(double d, Eigen::Index k, unsigned seed) {
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
  const Eigen::VectorXd y = draw_window_ranges(3000.0, 400, 3);
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
    const Eigen::VectorXd wall = draw_window_ranges(3000.0, 2000, seed);
    const Eigen::VectorXd object = draw_window_ranges(2700.0, 400, seed + 100);
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
  const Eigen::VectorXd y = draw_window_ranges(1000.0, 6, 9);
  for (Eigen::Index k = 0; k < 6; ++k) EXPECT_EQ(estimator.add(y[k]).restarting, k < 4) << k;
  EXPECT_THROW(estimator.add(INFINITY), InvalidInput);
  options.min_samples = 0;
  EXPECT_THROW(SlidingWindowEstimator(kModes, options), InvalidInput);
  options.min_samples = 5;
  options.refreshes = -1;
  EXPECT_THROW(SlidingWindowEstimator(kModes, options), InvalidInput);
}

// ---- The extended mixture (core/extended_mixture.hpp) ----

struct ExtendedCase {
  std::string name;
  ExtendedMixture noise;
  double mode2_slope = 0.0;  // mm per °C of the junction: mode 2's offset shift (0: none)
};

Term two_temperature_bins(Parameter parameter) {
  Term t;
  t.parameter = parameter;
  t.covariate = Covariate::JunctionTemperature;
  t.form = Form::Bins;
  t.knots = Eigen::VectorXd::Constant(1, 30.0);
  return t;
}

int state_at(const ExtendedMixture& m, double junction) {
  const int weight_bin = m.weight_bins ? term_bin(m.weight_bins->term, junction) : 0;
  const int variance_bin = m.variance_bins ? term_bin(m.variance_bins->term, junction) : 0;
  return m.state(weight_bin, variance_bin);
}

// One extension at a time, as a calibration carries them: two temperature bins (edge 30 °C)
// with their own weights or spreads, a Markov chain over the modes, an outlier component
// (5 % uniform over 400 mm), and a third mode (the paper's model with M = 3: no extension).
std::vector<ExtendedCase> extended_cases() {
  std::vector<ExtendedCase> cases;
  ExtendedMixture weights = without_extensions(kModes);
  weights.weight_bins =
      NoiseBins{two_temperature_bins(Parameter::Weights), Eigen::MatrixXd(2, 2), {}, {}};
  weights.weight_bins->table << 0.85, 0.15, 0.2, 0.8;
  cases.push_back({"bin weights", weights});
  ExtendedMixture spread = without_extensions(kModes);
  spread.variance_bins =
      NoiseBins{two_temperature_bins(Parameter::Spread), Eigen::MatrixXd(2, 2), {}, {}};
  spread.variance_bins->table << 0.5, 0.6, 2.5, 3.0;
  cases.push_back({"bin variances", spread});
  cases.push_back({"mode offset shift", without_extensions(kModes), 0.3});
  ExtendedMixture chain = without_extensions(kModes);
  chain.transition.resize(2, 2);
  chain.transition << 0.95, 0.05, 0.08, 0.92;
  cases.push_back({"mode chain", chain});
  ExtendedMixture outliers = without_extensions(kModes);
  outliers.outlier_weight = 0.05;
  outliers.outlier_density = 1.0 / 400.0;
  cases.push_back({"outliers", outliers});
  cases.push_back({"extra mode", without_extensions(testing::mixture(
                                     {-2.0, 2.5, 6.0}, {0.9, 1.1, 0.8}, {0.5, 0.4, 0.1}))});
  return cases;
}

struct ExtendedDraw {
  Eigen::VectorXd y;
  Eigen::VectorXi bin;
  Eigen::MatrixXd shift;  // K × M: each range's mode offset shifts (empty: none)
};

// Ranges at distance d drawn from the extended model itself; the junction sweeps 24..36 °C
// (both bins) over 300 ranges.
ExtendedDraw draw_extended(const ExtendedCase& c, double d, Eigen::Index k, unsigned seed) {
  const ExtendedMixture& noise = c.noise;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  const int m = noise.modes.modes();
  ExtendedDraw out{Eigen::VectorXd(k), Eigen::VectorXi(k), Eigen::MatrixXd(0, 0)};
  if (c.mode2_slope != 0.0) out.shift = Eigen::MatrixXd::Zero(k, m);
  int mode = 0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const double junction = 24.0 + 12.0 * static_cast<double>(j % 300) / 300.0;
    const int b = state_at(noise, junction);
    out.bin[j] = b;
    if (c.mode2_slope != 0.0) out.shift(j, 1) = c.mode2_slope * (junction - 30.0);
    double u = unit(rng);
    if (noise.transition.size() > 0 && j > 0) {
      int next = 0;
      while (next < m - 1 && u > noise.transition(mode, next)) u -= noise.transition(mode, next++);
      mode = next;
    } else {
      mode = 0;
      while (mode < m - 1 && u > noise.weight(b, mode)) u -= noise.weight(b, mode++);
    }
    if (noise.outlier_weight > 0.0 && unit(rng) < noise.outlier_weight) {
      out.y[j] = d + (unit(rng) - 0.5) / noise.outlier_density;
      continue;
    }
    out.y[j] = d + noise.modes.mean[mode] + (out.shift.size() > 0 ? out.shift(j, mode) : 0.0) +
               std::sqrt(noise.variance(b, mode)) * normal(rng);
  }
  return out;
}

// Exact: at every checked range the window's d̂ is test_extended_em of the latest W ranges with
// their bins, for each extension (to the EM's own tolerance); a window of the extended model
// never raises a false alarm. (Here the outliers' first range is one: the window, anchored on
// it, takes the wall for a run of outliers and restarts on the wall.)
TEST(SlidingWindowExtended, ExactEqualsBatchExtendedTest) {
  for (const ExtendedCase& c : extended_cases()) {
    SlidingWindowOptions options;
    options.window = 150;
    const bool shifted = c.mode2_slope != 0.0;
    SlidingWindowEstimator estimator(c.noise, options, shifted);
    const ExtendedDraw data = draw_extended(c, 3000.0, 600, 5);
    Eigen::Index start = 0;
    for (Eigen::Index k = 0; k < data.y.size(); ++k) {
      const WindowEstimate e = estimator.add(
          data.y[k], data.bin[k],
          shifted ? Eigen::VectorXd(data.shift.row(k).transpose()) : Eigen::VectorXd());
      if (e.change_detected) {
        // Only a window that started on an outlier is restarted, at the end of its run.
        ASSERT_LT(k, 20) << c.name;
        start = k;
      }
      if (k % 41 != 0 && k != data.y.size() - 1) continue;
      const Eigen::Index n = std::min<Eigen::Index>(k + 1 - start, 150);
      const auto batch = test_extended_em(
          data.y.segment(k + 1 - n, n), Eigen::VectorXd::Zero(n), data.bin.segment(k + 1 - n, n),
          shifted ? Eigen::MatrixXd(data.shift.middleRows(k + 1 - n, n)) : Eigen::MatrixXd(0, 0),
          c.noise);
      EXPECT_NEAR(e.distance, batch.distance, 1e-4) << c.name << " " << k;
      EXPECT_NEAR(e.distance_std, batch.distance_std, 1e-3 * batch.distance_std) << c.name;
      EXPECT_NEAR(
          (e.posterior - batch.responsibilities.row(n - 1).transpose()).cwiseAbs().maxCoeff(), 0.0,
          1e-3)
          << c.name << " " << k;
    }
  }
}

// Incremental: tracks test_extended_em of the latest W ranges on a stationary beam, within a
// fraction of d̂'s standard deviation σ_d (checked every 250 ranges over 100,000). The bins and
// the outlier component enter the incremental sums exactly as the batch E-step's, so the
// difference is only the responsibilities' age, as for the paper's mixture (rms < 0.2 σ_d,
// largest < 0.6 σ_d; measured 0.06-0.14 and 0.23-0.45).
// Under a chain the incremental E-step is the forward filter, not the batch smoother: the
// stated bound there is rms < 0.35 σ_d, largest < 1.5 σ_d (measured 0.22 and 0.78). The estimate is
// also close to the truth: |d̂ − d| < 5 σ_d on average.
TEST(SlidingWindowExtended, IncrementalTracksTheBatchExtendedTest) {
  for (const ExtendedCase& c : extended_cases()) {
    const bool shifted = c.mode2_slope != 0.0;
    SlidingWindowEstimator estimator(c.noise, incremental(200), shifted);
    const Eigen::Index n = 100000;
    const ExtendedDraw data = draw_extended(c, 3000.0, n, 23);
    double sum_square = 0.0;
    double largest = 0.0;
    double truth_square = 0.0;
    int checks = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
      const WindowEstimate e = estimator.add(
          data.y[k], data.bin[k],
          shifted ? Eigen::VectorXd(data.shift.row(k).transpose()) : Eigen::VectorXd());
      ASSERT_FALSE(e.change_detected) << c.name << " " << k;
      if ((k + 1) % 250 != 0) continue;
      const auto batch =
          test_extended_em(data.y.segment(k + 1 - 200, 200), Eigen::VectorXd::Zero(200),
                           data.bin.segment(k + 1 - 200, 200),
                           shifted ? Eigen::MatrixXd(data.shift.middleRows(k + 1 - 200, 200))
                                   : Eigen::MatrixXd(0, 0),
                           c.noise);
      const double z = (e.distance - batch.distance) / batch.distance_std;
      sum_square += z * z;
      truth_square += std::pow((e.distance - 3000.0) / batch.distance_std, 2);
      largest = std::max(largest, std::abs(z));
      ++checks;
      EXPECT_NEAR(e.distance_std, batch.distance_std, 0.15 * batch.distance_std) << c.name << k;
      if (c.noise.outlier_weight > 0.0) {
        EXPECT_GE(e.outlier, 0.0);
        EXPECT_LE(e.outlier, 1.0);
      }
    }
    const double rms = std::sqrt(sum_square / checks);
    std::printf("%s: incremental vs batch rms %.4f, largest %.4f, vs truth rms %.4f (sigma_d)\n",
                c.name.c_str(), rms, largest, std::sqrt(truth_square / checks));
    const bool chain = c.noise.transition.size() > 0;
    EXPECT_LT(rms, chain ? 0.35 : 0.2) << c.name;
    EXPECT_LT(largest, chain ? 1.5 : 0.6) << c.name;
    EXPECT_LT(std::sqrt(truth_square / checks), 5.0) << c.name;
  }
}

// An outlier far from the window is taken for one (responsibility near 1, flagged by the
// caller) and neither moves d̂ nor restarts the window; a run of them (6 at ε = 5 %: the
// smallest n with ε^n < 1e-7) is a change of scene.
TEST(SlidingWindowExtended, OutliersNeitherMoveNorRestartTheWindow) {
  ExtendedMixture noise;
  for (const ExtendedCase& c : extended_cases()) {
    if (c.name == "outliers") noise = c.noise;
  }
  ASSERT_GT(noise.outlier_weight, 0.0);
  for (const WindowEm method : {WindowEm::Exact, WindowEm::Incremental}) {
    SlidingWindowOptions options = incremental(200);
    options.method = method;
    SlidingWindowEstimator estimator(noise, options);
    const Eigen::VectorXd wall = draw_window_ranges(3000.0, 300, 4);
    WindowEstimate before;
    for (Eigen::Index k = 0; k < wall.size(); ++k) before = estimator.add(wall[k]);
    const WindowEstimate e = estimator.add(3150.0);
    EXPECT_FALSE(e.change_detected);
    EXPECT_GT(e.outlier, 0.99);
    EXPECT_NEAR(e.distance, before.distance, 0.05);
    estimator.add(wall[0]);
    for (int k = 0; k < 5; ++k) EXPECT_FALSE(estimator.add(2800.0 + k).change_detected) << k;
    EXPECT_TRUE(estimator.add(2805.0).change_detected);
    WindowEstimate last;
    for (int k = 0; k < 20; ++k) last = estimator.add(2800.0 + 0.1 * k);
    EXPECT_NEAR(last.distance, 2800.0, 3.0);
  }
}

// Without an extension the extended constructor is the plain one, bit for bit, both methods.
TEST(SlidingWindowExtended, NoExtensionIsThePlainMixtureBitForBit) {
  for (const WindowEm method : {WindowEm::Exact, WindowEm::Incremental}) {
    SlidingWindowOptions options = incremental(100);
    options.method = method;
    SlidingWindowEstimator plain(kModes, options);
    SlidingWindowEstimator extended(without_extensions(kModes), options);
    const Eigen::VectorXd y = draw_window_ranges(3000.0, 500, 8);
    for (Eigen::Index k = 0; k < y.size(); ++k) {
      const WindowEstimate a = plain.add(y[k]);
      const WindowEstimate b = extended.add(y[k], 0);
      ASSERT_EQ(a.distance, b.distance) << k;
      ASSERT_EQ(a.distance_std, b.distance_std) << k;
      ASSERT_EQ(a.posterior, b.posterior) << k;
      ASSERT_EQ(b.outlier, 0.0);
    }
    EXPECT_THROW(extended.add(y[0], 1), InvalidInput);
  }
}

}  // namespace
}  // namespace tofcomp::core
