// EM with one unknown distance per still episode (core/field_em.hpp) on ranges drawn from
// Eq. 8 with known θ, modes and distances: without any reference it recovers the bias's shape,
// the modes' spacing, spreads and weights, and every distance up to the one constant the data
// cannot give (the modes' mean offset, pinned); with a bench block of known distance it recovers
// them absolutely. The tolerances are a few standard errors of the drawn sample sizes.
#include "core/field_em.hpp"

#include <gtest/gtest.h>

#include <random>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

// The temperature band and the basis: Legendre P1, P2 of the temperature scaled to [−1, 1].
constexpr double kLowC = 30.0;
constexpr double kHighC = 60.0;

Eigen::RowVector2d basis_row(double temperature_c) {
  const double s = (2.0 * temperature_c - kLowC - kHighC) / (kHighC - kLowC);
  return {s, 0.5 * (3.0 * s * s - 1.0)};
}

struct Drawn {
  Eigen::MatrixXd h;
  Eigen::VectorXd y;
  std::vector<int> episode;
  Eigen::VectorXd distance;  // true d_e
  Eigen::Vector2d theta{4.0, 1.5};
  MixtureParameters mixture;
};

// `episodes` still surfaces at 0.8-8 m, each seen over its own stretch of temperatures 10-30 K
// wide, `per_episode` ranges each; then `bench` ranges of known distance in 35-40 °C.
Drawn draw_episodes(int episodes, int per_episode, int bench, unsigned seed) {
  Drawn d;
  d.mixture.mean = Eigen::Vector2d(-2.0, 6.0);
  d.mixture.variance = Eigen::Vector2d(1.5 * 1.5, 2.0 * 2.0);
  d.mixture.weight = Eigen::Vector2d(0.7, 0.3);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int k = episodes * per_episode + bench;
  d.h.resize(k, 2);
  d.y.resize(k);
  d.episode.resize(static_cast<std::size_t>(k));
  d.distance.resize(episodes);
  const auto noise = [&] {
    const int mode = unit(rng) < d.mixture.weight[0] ? 0 : 1;
    return d.mixture.mean[mode] + std::sqrt(d.mixture.variance[mode]) * normal(rng);
  };
  int row = 0;
  for (int e = 0; e < episodes; ++e) {
    d.distance[e] = 800.0 + 7200.0 * unit(rng);
    const double width = 10.0 + 20.0 * unit(rng);
    const double low = kLowC + (kHighC - kLowC - width) * unit(rng);
    for (int i = 0; i < per_episode; ++i, ++row) {
      const double t = low + width * unit(rng);
      d.h.row(row) = basis_row(t);
      d.y[row] = d.distance[e] + d.h.row(row).dot(d.theta) + noise();
      d.episode[static_cast<std::size_t>(row)] = e;
    }
  }
  for (int i = 0; i < bench; ++i, ++row) {
    const double t = 35.0 + 5.0 * unit(rng);
    d.h.row(row) = basis_row(t);
    d.y[row] = d.h.row(row).dot(d.theta) + noise();  // y − d, d known
    d.episode[static_cast<std::size_t>(row)] = kKnownDistance;
  }
  return d;
}

// The largest difference of two biases H(t)θ over the band.
double largest_bias_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double largest = 0.0;
  for (double t = kLowC; t <= kHighC; t += 0.5) {
    largest = std::max(largest, std::abs(basis_row(t).dot(a - b)));
  }
  return largest;
}

TEST(FieldEm, WithoutAReferenceRecoversAllButTheSharedConstant) {
  const Drawn d = draw_episodes(30, 1000, 0, 1);
  const FieldEmResult fit = train_field_em(d.h, d.y, d.episode, 30);
  EXPECT_TRUE(fit.converged);
  EXPECT_FALSE(fit.distance_determined);
  // The pin holds: the modes' mean offset is 0, so each d̂_e carries the true mean offset.
  EXPECT_NEAR(fit.mixture.mean_offset(), 0.0, 1e-9);
  const double shared = d.mixture.mean_offset();
  // A range's standard deviation is about 4 mm: d̂_e of 1000 ranges has a standard error near
  // 0.13 mm, θ's bias over 30,000 ranges a few hundredths (on 20 other seeds: the largest d̂_e
  // error 0.09-0.18 mm, the bias's 0.02-0.09 mm, the modes' spacing within 0.04 mm).
  for (int e = 0; e < 30; ++e) {
    EXPECT_NEAR(fit.episode_distance[e], d.distance[e] + shared, 0.5) << "episode " << e;
  }
  EXPECT_LT(largest_bias_difference(fit.theta, d.theta), 0.15);
  EXPECT_NEAR(fit.mixture.mean[1] - fit.mixture.mean[0], 8.0, 0.1);
  EXPECT_NEAR(fit.mixture.weight[0], 0.7, 0.02);
  EXPECT_NEAR(std::sqrt(fit.mixture.variance[0]), 1.5, 0.05);
  EXPECT_NEAR(std::sqrt(fit.mixture.variance[1]), 2.0, 0.08);
}

TEST(FieldEm, APinnedMeanOffsetMovesOnlyTheDistances) {
  const Drawn d = draw_episodes(12, 800, 0, 2);
  const FieldEmResult zero = train_field_em(d.h, d.y, d.episode, 12);
  FieldEmOptions pinned;
  pinned.pinned_mean_offset_mm = 3.0;
  const FieldEmResult three = train_field_em(d.h, d.y, d.episode, 12, pinned);
  EXPECT_NEAR(three.mixture.mean_offset(), 3.0, 1e-9);
  EXPECT_LT(largest_bias_difference(zero.theta, three.theta), 1e-6);
  EXPECT_LT((three.episode_distance.array() - zero.episode_distance.array() + 3.0).abs().maxCoeff(),
            1e-6);
  EXPECT_NEAR(three.log_likelihood, zero.log_likelihood, 1e-6 * std::abs(zero.log_likelihood));
}

TEST(FieldEm, ABenchBlockOfKnownDistanceFixesTheAbsoluteLevel) {
  // The bench sees 35-40 °C only; the field days the whole band.
  const Drawn d = draw_episodes(20, 1000, 5000, 3);
  const FieldEmResult fit = train_field_em(d.h, d.y, d.episode, 20);
  EXPECT_TRUE(fit.distance_determined);
  for (int e = 0; e < 20; ++e) {
    EXPECT_NEAR(fit.episode_distance[e], d.distance[e], 0.5) << "episode " << e;
  }
  EXPECT_NEAR(fit.mixture.mean[0], -2.0, 0.15);
  EXPECT_NEAR(fit.mixture.mean[1], 6.0, 0.15);
  EXPECT_LT(largest_bias_difference(fit.theta, d.theta), 0.2);
}

TEST(FieldEm, AStartFromABenchCalibrationEndsAtTheSameFit) {
  const Drawn d = draw_episodes(10, 1000, 2000, 4);
  const FieldEmResult cold = train_field_em(d.h, d.y, d.episode, 10);
  FieldEmOptions warm;
  warm.start = EmStartingPoint{Eigen::Vector2d(3.0, 0.0), d.mixture};
  const FieldEmResult fit = train_field_em(d.h, d.y, d.episode, 10, warm);
  EXPECT_LT(largest_bias_difference(fit.theta, cold.theta), 1e-3);
  EXPECT_LT((fit.episode_distance - cold.episode_distance).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(FieldEm, BadArgumentsAreNamed) {
  const Drawn d = draw_episodes(3, 100, 0, 5);
  std::vector<int> outside = d.episode;
  outside[7] = 3;
  try {
    train_field_em(d.h, d.y, outside, 3);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "field EM training: range 7 names episode 3, outside 0..2");
  }
  try {
    train_field_em(d.h, d.y, d.episode, 4);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "field EM training: episode 3 has no range");
  }
  EXPECT_THROW(train_field_em(d.h.topRows(5), d.y.head(5), std::vector<int>(5, 0), 1),
               InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
