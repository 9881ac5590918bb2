// The model search's basis design (calibration/model_spec.hpp, SearchData): Q orthogonal on all
// the ranges, and each of its directions determined on each half of them. The answers are known
// by construction: a column that is non-zero on a few ranges of one half only is a direction the
// other half cannot see, and nothing else is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "calibration/model_spec.hpp"

namespace tofcomp::calibration {
namespace {

constexpr Eigen::Index kSearchRanges = 400;
constexpr Eigen::Index kBlock = 20;  // ranges per block, alternating between the halves
constexpr double kMinimumRanges = 10.0;

core::CovariateTable covariates() {
  core::CovariateSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(kSearchRanges, 0.0, static_cast<double>(kSearchRanges - 1));
  s.junction_c = Eigen::VectorXd::LinSpaced(kSearchRanges, 25.0, 35.0);
  s.time_since_power_on_s = s.time_s;
  return core::CovariateTable(std::move(s));
}

std::vector<Eigen::Index> first_half() {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index k = 0; k < kSearchRanges; ++k) {
    if ((k / kBlock) % 2 == 0) rows.push_back(k);
  }
  return rows;
}

// A linear and a quadratic of the temperature, plus (when `spike`) a column that is one on three
// ranges of the second half's first block and zero elsewhere.
Eigen::MatrixXd design(bool spike) {
  const Eigen::ArrayXd x = Eigen::ArrayXd::LinSpaced(kSearchRanges, -1.0, 1.0);
  Eigen::MatrixXd h(kSearchRanges, spike ? 3 : 2);
  h.col(0) = x.matrix();
  h.col(1) = (x * x).matrix();
  if (spike) {
    h.col(2).setZero();
    for (const Eigen::Index k : {kBlock + 1, kBlock + 5, kBlock + 9}) h(k, 2) = 1.0;
  }
  return h;
}

Eigen::VectorXd noise(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd y(kSearchRanges);
  for (Eigen::Index k = 0; k < kSearchRanges; ++k) y[k] = normal(rng);
  return y;
}

TEST(SearchData, KeepsEveryDirectionBothHalvesDetermine) {
  const Eigen::Vector2d theta(0.7, -1.3);
  const Eigen::VectorXd y = noise(1);
  const SearchData data(y, design(false), covariates(), theta, first_half(), kMinimumRanges);
  EXPECT_EQ(data.directions_undetermined_by_a_half(), 0);
  EXPECT_EQ(data.basis_design().cols(), 2);
  EXPECT_EQ(data.y(), y);
  // θ → Q's coordinates → θ is exact for any θ when nothing is held.
  const Eigen::Vector2d other(-2.0, 0.4);
  Eigen::VectorXd orthogonal, mean = Eigen::VectorXd::Zero(2), back;
  data.to_orthogonal(other, orthogonal, mean);
  data.to_basis(orthogonal, back, mean);
  EXPECT_NEAR((back - other).cwiseAbs().maxCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(mean.cwiseAbs().maxCoeff(), 0.0, 1e-12);
}

TEST(SearchData, HoldsTheDirectionOneHalfDoesNotSeeAtTheTrainingsFit) {
  // The training's bias: a quadratic of the temperature and the spike.
  const Eigen::Vector3d trained(0.7, -1.3, 5.0);
  const Eigen::VectorXd y = noise(2);
  const SearchData data(y, design(true), covariates(), trained, first_half(), kMinimumRanges);
  EXPECT_EQ(data.directions_undetermined_by_a_half(), 1);
  const Eigen::MatrixXd& q = data.basis_design();
  ASSERT_EQ(q.cols(), 2);
  // Still orthogonal on all the ranges (QᵀQ = K I) ...
  const Eigen::MatrixXd gram = q.transpose() * q / static_cast<double>(kSearchRanges);
  EXPECT_NEAR((gram - Eigen::MatrixXd::Identity(2, 2)).cwiseAbs().maxCoeff(), 0.0, 1e-10);
  // ... and each half holds each kept direction.
  const Eigen::MatrixXd half = q(first_half(), Eigen::all);
  const Eigen::VectorXd share =
      (half.transpose() * half).diagonal() / static_cast<double>(kSearchRanges);
  EXPECT_GT(share.minCoeff() * kSearchRanges, kMinimumRanges);
  EXPECT_LT(share.maxCoeff() * kSearchRanges, kSearchRanges - kMinimumRanges);
  // The training's bias is split exactly between Q's part and the part held (subtracted from
  // y − d), up to the constant the offsets carry, and comes back whole.
  const Eigen::MatrixXd h = design(true);
  Eigen::VectorXd orthogonal, mean = Eigen::VectorXd::Zero(2), back;
  data.to_orthogonal(trained, orthogonal, mean);
  const Eigen::VectorXd held = y - data.y();
  const Eigen::VectorXd split = h * trained - q * orthogonal - held;
  EXPECT_NEAR((split.array() - split.mean()).abs().maxCoeff(), 0.0, 1e-9);
  data.to_basis(orthogonal, back, mean);
  EXPECT_NEAR((back - trained).cwiseAbs().maxCoeff(), 0.0, 1e-9);
  EXPECT_NEAR(mean.cwiseAbs().maxCoeff(), 0.0, 1e-9);
  // What is held is mostly the spike: on its three ranges, not elsewhere.
  const std::vector<Eigen::Index> spike_rows{kBlock + 1, kBlock + 5, kBlock + 9};
  double on_spike = 0.0, elsewhere = 0.0;
  for (Eigen::Index k = 0; k < kSearchRanges; ++k) {
    const bool spike = std::find(spike_rows.begin(), spike_rows.end(), k) != spike_rows.end();
    (spike ? on_spike : elsewhere) += held[k] * held[k];
  }
  EXPECT_GT(on_spike, 10.0 * elsewhere);
  // With no direction held (a threshold of zero ranges) the spike is Q's.
  const SearchData everything(y, design(true), covariates(), trained, first_half(), 0.0);
  EXPECT_EQ(everything.directions_undetermined_by_a_half(), 0);
  EXPECT_EQ(everything.basis_design().cols(), 3);
}

}  // namespace
}  // namespace tofcomp::calibration
