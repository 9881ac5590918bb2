#include "core/mixture_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/column_products.hpp"
#include "core/error.hpp"
#include "core/vector_math.hpp"
#include "core/weighted_least_squares.hpp"

namespace tofcomp::core {
namespace {

// Ranges per chunk: a chunk's arrays (a few columns of this many doubles) stay in the L1/L2
// cache, and the per-chunk matrix products are long enough to run at speed.
constexpr Eigen::Index kChunk = 512;

}  // namespace

Eigen::RowVectorXd ExactStepSums::weighted_mean() const {
  const double total = mode_weight.sum();
  return centre + (mode_sums.rowwise().sum().transpose() / total);
}

ExactStepSums exact_step_sweep(const Eigen::Ref<const Eigen::MatrixXd>& h,
                               const Eigen::Ref<const Eigen::VectorXd>& y,
                               const Eigen::VectorXd& theta, const MixtureParameters& mixture,
                               const Eigen::RowVectorXd& centre, Eigen::MatrixXd& responsibilities) {
  const Eigen::Index k = y.size();
  const Eigen::Index p = h.cols();
  const int m = mixture.modes();
  responsibilities.resize(k, m);
  // Per mode: log π_i − ½ log(2π σ_i²), −1/(2σ_i²) and 1/σ_i² (Eq. 18's Gaussian densities).
  Eigen::ArrayXd log_constant(m), minus_half_precision(m), precision(m);
  for (int i = 0; i < m; ++i) {
    log_constant[i] = std::log(mixture.weight[i]) -
                      0.5 * std::log(2.0 * std::numbers::pi * mixture.variance[i]);
    precision[i] = 1.0 / mixture.variance[i];
    minus_half_precision[i] = -0.5 * precision[i];
  }

  ExactStepSums s;
  s.centre = centre;
  s.gram = Eigen::MatrixXd::Zero(p, p);
  s.gram_rhs = Eigen::VectorXd::Zero(p);
  s.mode_sums = Eigen::MatrixXd::Zero(p, m);
  s.mode_weight = Eigen::VectorXd::Zero(m);
  s.mode_target = Eigen::VectorXd::Zero(m);
  s.mass = Eigen::VectorXd::Zero(m);
  Eigen::ArrayXXd joint(kChunk, m);
  Eigen::ArrayXd residual(kChunk), top(kChunk), total(kChunk), log_total(kChunk), root(kChunk);
  Eigen::MatrixXd centred(kChunk, p);
  Eigen::MatrixXd weights(kChunk, m);
  double log_likelihood = 0.0;
  for (Eigen::Index first = 0; first < k; first += kChunk) {
    const Eigen::Index n = std::min(kChunk, k - first);
    const auto h_chunk = h.middleRows(first, n);
    const auto y_chunk = y.segment(first, n).array();
    auto e = residual.head(n);
    e = y_chunk;
    subtract_product(h_chunk, theta, e.matrix());
    // log π_i N(e_k; μ_i, σ_i²), and its largest over the modes.
    auto lj = joint.topRows(n);
    for (int i = 0; i < m; ++i) {
      lj.col(i) = (e - mixture.mean[i]).square() * minus_half_precision[i] + log_constant[i];
    }
    auto t = top.head(n);
    t = lj.col(0);
    for (int i = 1; i < m; ++i) t = t.max(lj.col(i));
    for (int i = 0; i < m; ++i) {
      lj.col(i) -= t;
      exp_in_place(lj.col(i));
    }
    auto sum = total.head(n);
    sum = lj.col(0);
    for (int i = 1; i < m; ++i) sum += lj.col(i);
    auto log_sum = log_total.head(n);
    log_sum = sum;
    log_in_place(log_sum);
    log_likelihood += (t + log_sum).sum();
    // r_ki, w_ki = r_ki / σ_i² and t_k = Σ_i w_ki (one division per range).
    sum = sum.inverse();
    auto r = responsibilities.middleRows(first, n);
    auto w = weights.topRows(n);
    auto root_t = root.head(n);
    root_t.setZero();
    for (int i = 0; i < m; ++i) {
      r.col(i) = (lj.col(i) * sum).matrix();
      w.col(i) = r.col(i) * precision[i];
      root_t += w.col(i).array();
    }
    s.mass += r.colwise().sum().transpose();
    s.mode_weight += w.colwise().sum().transpose();
    s.mode_target.noalias() += w.transpose().lazyProduct(y.segment(first, n));
    // x_k = √t_k (H_k − c) in one pass; then Σ_k w_ki (H_k − c) = xᵀ (w_i / √t), the Gram
    // matrix and its right-hand side (the chunk is in cache).
    root_t = root_t.sqrt();
    auto x = centred.topRows(n);
    scale_centred_rows(h_chunk, centre, root_t.matrix(), x);
    auto w_over_root = w.array().colwise() / root_t;
    w = w_over_root.matrix();
    add_cross_products(x, w, s.mode_sums);
    add_lower_gram(x, s.gram);
    root_t *= y_chunk;  // √t_k y_k, for the right-hand side xᵀ (√t y)
    add_cross_products(x, root_t.matrix(), s.gram_rhs);
  }
  if (!std::isfinite(log_likelihood)) {
    throw NumericalError(
        "mixture log-likelihood is not finite: a residual is not finite or every mode has zero "
        "weight");
  }
  s.gram.triangularView<Eigen::StrictlyUpper>() = s.gram.transpose();
  s.log_likelihood = log_likelihood;
  return s;
}

void exact_step_solve(const Eigen::Ref<const Eigen::MatrixXd>& h,
                      const Eigen::Ref<const Eigen::VectorXd>& y, const ExactStepSums& s,
                      const Eigen::MatrixXd& responsibilities, double floor,
                      Eigen::VectorXd& theta, MixtureParameters& mixture) {
  const Eigen::Index k = y.size();
  const Eigen::Index p = h.cols();
  const int m = static_cast<int>(s.mass.size());
  // μ profiled out: (G − Σ_i S_i S_iᵀ / s_i) θ = b − Σ_i S_i c_i / s_i, then
  // μ_i + c θ = (c_i − S_iᵀ θ) / s_i (core/mode_regression.hpp, centred on c).
  Eigen::VectorXd mean(m);
  if (p > 0) {
    Eigen::MatrixXd g = s.gram;
    Eigen::VectorXd b = s.gram_rhs;
    for (int i = 0; i < m; ++i) {
      g.noalias() -= s.mode_sums.col(i) * s.mode_sums.col(i).transpose() / s.mode_weight[i];
      b.noalias() -= s.mode_sums.col(i) * (s.mode_target[i] / s.mode_weight[i]);
    }
    theta = solve_normal_equations(g, b, "the weighted normal matrix HᵀC⁻¹H of the M-step");
    const double centred_bias = s.centre.dot(theta);
    mean = ((s.mode_target - s.mode_sums.transpose() * theta).array() / s.mode_weight.array() -
            centred_bias)
               .matrix();
  } else {
    theta.resize(0);
    mean = (s.mode_target.array() / s.mode_weight.array()).matrix();
  }
  // σ_i² = Σ_k r_ki (ỹ_k − H_k θ − μ_i)² / Σ_k r_ki at the new θ, μ; π_i = Σ_k r_ki / K.
  Eigen::ArrayXd square = Eigen::ArrayXd::Zero(m);
  Eigen::ArrayXd residual(kChunk);
  for (Eigen::Index first = 0; first < k; first += kChunk) {
    const Eigen::Index n = std::min(kChunk, k - first);
    auto e = residual.head(n);
    e = y.segment(first, n).array();
    if (p > 0) subtract_product(h.middleRows(first, n), theta, e.matrix());
    const auto r = responsibilities.middleRows(first, n);
    for (int i = 0; i < m; ++i) square[i] += (r.col(i).array() * (e - mean[i]).square()).sum();
  }
  mixture.mean = mean;
  mixture.variance = (square / s.mass.array()).max(floor).matrix();
  mixture.weight = s.mass / static_cast<double>(k);
  mixture.weight /= mixture.weight.sum();
}

}  // namespace tofcomp::core
