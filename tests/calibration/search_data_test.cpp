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

constexpr Eigen::Index kRanges = 400;
constexpr Eigen::Index kBlock = 20;  // ranges per block, alternating between the halves
constexpr double kMinimumRanges = 10.0;

core::CovariateTable covariates() {
  core::CovariateSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(kRanges, 0.0, static_cast<double>(kRanges - 1));
  s.junction_c = Eigen::VectorXd::LinSpaced(kRanges, 25.0, 35.0);
  s.time_since_power_on_s = s.time_s;
  return core::CovariateTable(std::move(s));
}

std::vector<Eigen::Index> first_half() {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index k = 0; k < kRanges; ++k) {
    if ((k / kBlock) % 2 == 0) rows.push_back(k);
  }
  return rows;
}

// A linear and a quadratic of the temperature, plus (when `spike`) a column that is one on three
// ranges of the second half's first block and zero elsewhere.
Eigen::MatrixXd design(bool spike) {
  const Eigen::ArrayXd x = Eigen::ArrayXd::LinSpaced(kRanges, -1.0, 1.0);
  Eigen::MatrixXd h(kRanges, spike ? 3 : 2);
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
  Eigen::VectorXd y(kRanges);
  for (Eigen::Index k = 0; k < kRanges; ++k) y[k] = normal(rng);
  return y;
}

TEST(SearchData, KeepsEveryDirectionBothHalvesDetermine) {
  const SearchData data(noise(1), design(false), covariates(), first_half(), kMinimumRanges);
  EXPECT_EQ(data.directions_undetermined_by_a_half(), 0);
  EXPECT_EQ(data.basis_design().cols(), 2);
  // θ → Q's coordinates → θ is exact when nothing is dropped.
  const Eigen::Vector2d theta(0.7, -1.3);
  Eigen::VectorXd orthogonal, mean = Eigen::VectorXd::Zero(2), back;
  data.to_orthogonal(theta, orthogonal, mean);
  data.to_basis(orthogonal, back, mean);
  EXPECT_NEAR((back - theta).cwiseAbs().maxCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(mean.cwiseAbs().maxCoeff(), 0.0, 1e-12);
}

TEST(SearchData, DropsTheDirectionOneHalfDoesNotSee) {
  const SearchData data(noise(2), design(true), covariates(), first_half(), kMinimumRanges);
  EXPECT_EQ(data.directions_undetermined_by_a_half(), 1);
  const Eigen::MatrixXd& q = data.basis_design();
  ASSERT_EQ(q.cols(), 2);
  // Still orthogonal on all the ranges (QᵀQ = K I) ...
  const Eigen::MatrixXd gram = q.transpose() * q / static_cast<double>(kRanges);
  EXPECT_NEAR((gram - Eigen::MatrixXd::Identity(2, 2)).cwiseAbs().maxCoeff(), 0.0, 1e-10);
  // ... and each half sees each kept direction.
  const Eigen::MatrixXd half = q(first_half(), Eigen::all);
  const Eigen::VectorXd share =
      (half.transpose() * half).diagonal() / static_cast<double>(kRanges);
  EXPECT_GT(share.minCoeff() * kRanges, kMinimumRanges);
  EXPECT_LT(share.maxCoeff() * kRanges, kRanges - kMinimumRanges);
  // A bias of the temperature alone survives the round trip (up to the constant the offsets
  // carry) away from the spike's ranges: what is dropped is mostly the spike. (The dropped
  // eigenvector mixes in a little of the other two directions, so not exactly.)
  const Eigen::Vector3d theta(0.7, -1.3, 0.0);
  Eigen::VectorXd orthogonal, mean = Eigen::VectorXd::Zero(2), back;
  data.to_orthogonal(theta, orthogonal, mean);
  data.to_basis(orthogonal, back, mean);
  const Eigen::MatrixXd h = design(true);
  const Eigen::VectorXd bias = h * theta;
  const Eigen::VectorXd gap = bias - h * back;
  const std::vector<Eigen::Index> spike_rows{kBlock + 1, kBlock + 5, kBlock + 9};
  std::vector<Eigen::Index> other_rows;
  for (Eigen::Index k = 0; k < kRanges; ++k) {
    if (std::find(spike_rows.begin(), spike_rows.end(), k) == spike_rows.end()) {
      other_rows.push_back(k);
    }
  }
  const Eigen::VectorXd gap_elsewhere = gap(other_rows);
  const double spread = bias.maxCoeff() - bias.minCoeff();
  EXPECT_LT((gap_elsewhere.array() - gap_elsewhere.mean()).abs().maxCoeff(), 0.05 * spread);
  // The spike's own coefficient is what the first half cannot determine: Q carries little of
  // it, where a Q that keeps every direction carries it whole.
  const Eigen::Vector3d spike(0.0, 0.0, 5.0);
  data.to_orthogonal(spike, orthogonal, mean);
  const SearchData everything(noise(2), design(true), covariates(), first_half(), 0.0);
  EXPECT_EQ(everything.directions_undetermined_by_a_half(), 0);
  Eigen::VectorXd whole;
  everything.to_orthogonal(spike, whole, mean);
  const double spike_norm = 5.0 * std::sqrt(3.0 / static_cast<double>(kRanges));
  EXPECT_NEAR(whole.norm(), spike_norm, 0.05 * spike_norm);
  EXPECT_LT(orthogonal.norm(), 0.25 * spike_norm);
}

}  // namespace
}  // namespace tofcomp::calibration
