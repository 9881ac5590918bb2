// The family-wise level of a search that names one of several candidates and keeps it when its
// t statistic is large: the max-T method (Westfall and Young, 1993, §2.6) with the null law of the
// largest t drawn by flipping the signs of the blocks (a randomization test).
//
// Each candidate j has a value per block, g_bj (its held-out gain over block b; the same blocks
// for every candidate), and the one-sided statistic t_j = mean_b g_bj / (sd_b g_bj / √n). When no
// candidate adds anything, each g_·j has mean ≤ 0 and its blocks are independent; flipping the
// signs of the centred values g_bj − ḡ_j of the same blocks for every candidate at once keeps the
// candidates' dependence on one another (they share the blocks' ranges: a bias and a mode-offset
// term on the same covariate gain on the same blocks) and gives a draw of the t statistics under
// a null of mean zero, the least favourable one. The adjusted p of a statistic t is the share of
// draws whose largest t reaches it. Keeping a candidate when its adjusted p is at most α keeps
// anything at all, on data where nothing is missing, with probability at most α however the
// candidate was picked, and, unlike α / m (Bonferroni), without paying for candidates that are
// near copies of one another.
//
// The draws come from a fixed-seed std::mt19937_64, whose output the standard fixes, so a result
// is the same on every machine and at every thread count.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace tofcomp::core {

// One gain summed over independent blocks, tested against zero: the one-sided t statistic of
// SignFlipMaxT::t_statistic and P(T ≥ t) under Student's t with blocks − 1 degrees of freedom
// (t 0, p 1 with fewer than two blocks). A candidate's own test, beside the family-wise one.
struct BlockGainTest {
  double t = 0.0;
  double p = 1.0;
};
BlockGainTest block_gain_t_test(const Eigen::Ref<const Eigen::VectorXd>& block_gains);

// The null law of the largest t over the candidates.
class SignFlipMaxT {
 public:
  // `block_values`: n blocks × m candidates. A column that does not vary is left out (its t is
  // not defined); InvalidInput on fewer than two blocks, no column, or a non-finite value.
  explicit SignFlipMaxT(const Eigen::Ref<const Eigen::MatrixXd>& block_values,
                        int draws = kDefaultDraws);

  // (1 + #{draws whose largest t ≥ t}) / (1 + draws).
  double adjusted_p(double t) const;
  // The largest t of a draw that a kept statistic must exceed at level alpha: adjusted_p(t) ≤
  // alpha exactly when t is above it (+∞ when alpha is below the smallest adjusted p).
  double critical_t(double alpha) const;
  int draws() const { return static_cast<int>(maxima_.size()); }

  // The one-sided t statistic of one column of block values; one that does not vary: +∞ when
  // positive (every block gains), else 0.
  static double t_statistic(const Eigen::Ref<const Eigen::VectorXd>& values);

  // Enough draws that an adjusted p of 0.05 is known to ±0.0022 (one standard error).
  static constexpr int kDefaultDraws = 9999;

 private:
  std::vector<double> maxima_;  // the draws' largest t, in increasing order
};

}  // namespace tofcomp::core
