#include "core/sign_flip_max_t.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "core/statistical_tests.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The fixed seed of the sign draws (any value; fixed so that results repeat).
constexpr std::uint64_t kSignSeed = 19930101;
// Draws whose sums are formed at once (a matrix product of ±1 rows with the centred blocks).
constexpr Eigen::Index kDrawsPerProduct = 256;
constexpr int kBitsPerWord = 64;

// t of a column from its sum S of signed centred values and its Σ of squares q over n blocks:
// mean S/n, variance (q − S²/n)/(n − 1), so t = S √(n − 1) / √(n q − S²).
double t_of_sum(double sum, double squares, double n) {
  const double spread = n * squares - sum * sum;
  if (!(spread > 0.0)) return sum > 0.0 ? kInfinity : (sum < 0.0 ? -kInfinity : 0.0);
  return sum * std::sqrt(n - 1.0) / std::sqrt(spread);
}

}  // namespace

double SignFlipMaxT::t_statistic(const Eigen::Ref<const Eigen::VectorXd>& values) {
  const auto n = static_cast<double>(values.size());
  if (n < 2.0) return 0.0;
  const double mean = values.mean();
  const double variance = (values.array() - mean).square().sum() / (n - 1.0);
  if (!(variance > 0.0)) return mean > 0.0 ? kInfinity : 0.0;
  return mean / std::sqrt(variance / n);
}

BlockGainTest block_gain_t_test(const Eigen::Ref<const Eigen::VectorXd>& block_gains) {
  if (block_gains.size() < 2) return {};
  const double t = SignFlipMaxT::t_statistic(block_gains);
  return {t, student_upper_tail(t, static_cast<double>(block_gains.size()) - 1.0)};
}

SignFlipMaxT::SignFlipMaxT(const Eigen::Ref<const Eigen::MatrixXd>& block_values, int draws) {
  const Eigen::Index n = block_values.rows();
  if (n < 2) throw InvalidInput("the max-T calibration needs at least two blocks");
  if (block_values.cols() < 1) throw InvalidInput("the max-T calibration needs a candidate");
  if (draws < 1) throw InvalidInput("the max-T calibration needs at least one draw");
  require_finite(block_values, "block values");
  // The centred columns that vary; the others have no t.
  std::vector<Eigen::Index> varying;
  for (Eigen::Index j = 0; j < block_values.cols(); ++j) {
    const auto column = block_values.col(j).array();
    if ((column - column.mean()).square().sum() > 0.0) varying.push_back(j);
  }
  maxima_.assign(static_cast<std::size_t>(draws), kInfinity);
  if (varying.empty()) return;  // nothing can be kept: every adjusted p is 1
  const Eigen::MatrixXd kept = block_values(Eigen::all, varying);
  const Eigen::MatrixXd centred = kept.rowwise() - kept.colwise().mean();
  const Eigen::RowVectorXd squares = centred.colwise().squaredNorm();
  const auto blocks = static_cast<double>(n);

  std::mt19937_64 engine(kSignSeed);
  Eigen::MatrixXd signs(kDrawsPerProduct, n);
  for (Eigen::Index first = 0; first < draws; first += kDrawsPerProduct) {
    const Eigen::Index count = std::min<Eigen::Index>(kDrawsPerProduct, draws - first);
    // Each draw's signs from the engine's bits, 64 blocks per word.
    for (Eigen::Index d = 0; d < count; ++d) {
      std::uint64_t word = 0;
      for (Eigen::Index b = 0; b < n; ++b) {
        if (b % kBitsPerWord == 0) word = engine();
        signs(d, b) = (word & 1U) != 0U ? 1.0 : -1.0;
        word >>= 1U;
      }
    }
    const Eigen::MatrixXd sums = signs.topRows(count) * centred;
    for (Eigen::Index d = 0; d < count; ++d) {
      double largest = -kInfinity;
      for (Eigen::Index j = 0; j < sums.cols(); ++j) {
        largest = std::max(largest, t_of_sum(sums(d, j), squares[j], blocks));
      }
      maxima_[static_cast<std::size_t>(first + d)] = largest;
    }
  }
  std::sort(maxima_.begin(), maxima_.end());
}

double SignFlipMaxT::adjusted_p(double t) const {
  // Draws whose largest t is ≥ t: those from the first not below t to the end.
  const auto at_or_above =
      maxima_.end() - std::lower_bound(maxima_.begin(), maxima_.end(), t);
  return (1.0 + static_cast<double>(at_or_above)) / (1.0 + static_cast<double>(maxima_.size()));
}

double SignFlipMaxT::critical_t(double alpha) const {
  // adjusted_p(t) ≤ alpha ⇔ #{maxima ≥ t} ≤ alpha (1 + draws) − 1 =: allowed; with the maxima
  // sorted that holds for every t above the (allowed + 1)-th largest.
  const double allowed = std::floor(alpha * (1.0 + static_cast<double>(maxima_.size())) - 1.0);
  if (allowed < 0.0) return kInfinity;
  if (allowed >= static_cast<double>(maxima_.size())) return -kInfinity;
  return maxima_[maxima_.size() - 1 - static_cast<std::size_t>(allowed)];
}

}  // namespace tofcomp::core
