#include "core/mixture_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/column_products.hpp"
#include "core/error.hpp"
#include "core/vector_math.hpp"

#if defined(TOFCOMP_VECTOR_MATH_AVX2)
#include "core/mixture_sweep_avx2.hpp"
#endif
#include "core/weighted_least_squares.hpp"

namespace tofcomp::core {
namespace {

// Ranges per chunk: a chunk's arrays (a few columns of this many doubles) stay in the L1/L2
// cache, and the per-chunk matrix products are long enough to run at speed.
constexpr Eigen::Index kMixtureSweepChunk = 512;
// Ranges per stripe: the sweeps' unit of work on the caller's threads. Each stripe's sums start
// from zero and the stripes' are added in order, so the answer depends on this size, never on
// the threads that ran the stripes. Long enough that a hand-off (a few microseconds) is small
// against a stripe's work (about 40 µs at 10 ns a range), short enough to balance two cores.
constexpr Eigen::Index kStripe = 8 * kMixtureSweepChunk;

int stripe_count(Eigen::Index k) { return static_cast<int>((k + kStripe - 1) / kStripe); }

// body(stripe, begin, end) for each stripe of [0, k), through parallel_for when there is one.
template <class Body>
void for_each_stripe(Eigen::Index k, const ParallelFor& parallel_for, const Body& body) {
  const int stripes = stripe_count(k);
  const auto run = [&](int stripe) {
    const Eigen::Index begin = static_cast<Eigen::Index>(stripe) * kStripe;
    body(stripe, begin, std::min(k, begin + kStripe));
  };
  if (parallel_for && stripes > 1) {
    parallel_for(stripes, run);
  } else {
    for (int stripe = 0; stripe < stripes; ++stripe) run(stripe);
  }
}

// The per-mode constants of Eq. 18's Gaussian densities: log π_i − ½ log(2π σ_i²), −1/(2σ_i²),
// 1/σ_i² and μ_i.
struct ModeConstants {
  Eigen::ArrayXd log_constant, minus_half_precision, precision, mean;
  explicit ModeConstants(const MixtureParameters& mixture) {
    const int m = mixture.modes();
    log_constant.resize(m);
    minus_half_precision.resize(m);
    precision.resize(m);
    mean = mixture.mean.array();
    for (int i = 0; i < m; ++i) {
      log_constant[i] = std::log(mixture.weight[i]) -
                        0.5 * std::log(2.0 * std::numbers::pi * mixture.variance[i]);
      precision[i] = 1.0 / mixture.variance[i];
      minus_half_precision[i] = -0.5 * precision[i];
    }
  }
  int modes() const { return static_cast<int>(mean.size()); }
};

// A chunk's working arrays for the portable E-step.
struct EStepScratch {
  Eigen::ArrayXXd joint;
  Eigen::ArrayXd top, total, log_total;
  explicit EStepScratch(int modes)
      : joint(kMixtureSweepChunk, modes), top(kMixtureSweepChunk), total(kMixtureSweepChunk), log_total(kMixtureSweepChunk) {}
};

using ChunkRows = Eigen::Block<Eigen::MatrixXd>;
using ChunkArray = Eigen::VectorBlock<Eigen::ArrayXd>;

// One chunk's E-step (Eq. 18) and the exact step's weights, portable: the responsibilities r_ki;
// with w_ki = r_ki / σ_i² and t_k = Σ_i w_ki, the modes' Σ r, Σ w and Σ w y added to the sums;
// into w, root_t and root_t_y the scaled forms the products take: w_ki / √t_k, √t_k, √t_k y_k.
// Returns the chunk's log-likelihood.
double portable_e_step(const ChunkArray& e, const Eigen::Ref<const Eigen::VectorXd>& y,
                       const ModeConstants& c, EStepScratch& scratch, ChunkRows& r, ChunkRows& w,
                       ChunkArray& root_t, ChunkArray& root_t_y, ExactStepSums& s) {
  const Eigen::Index n = e.size();
  const int m = c.modes();
  // log π_i N(e_k; μ_i, σ_i²), and its largest over the modes.
  auto lj = scratch.joint.topRows(n);
  for (int i = 0; i < m; ++i) {
    lj.col(i) = (e - c.mean[i]).square() * c.minus_half_precision[i] + c.log_constant[i];
  }
  auto t = scratch.top.head(n);
  t = lj.col(0);
  for (int i = 1; i < m; ++i) t = t.max(lj.col(i));
  for (int i = 0; i < m; ++i) {
    lj.col(i) -= t;
    exp_in_place(lj.col(i));
  }
  auto sum = scratch.total.head(n);
  sum = lj.col(0);
  for (int i = 1; i < m; ++i) sum += lj.col(i);
  auto log_sum = scratch.log_total.head(n);
  log_sum = sum;
  log_in_place(log_sum);
  const double log_likelihood = (t + log_sum).sum();
  // r_ki, w_ki = r_ki / σ_i² and t_k = Σ_i w_ki (one division per range).
  sum = sum.inverse();
  root_t.setZero();
  for (int i = 0; i < m; ++i) {
    r.col(i) = (lj.col(i) * sum).matrix();
    w.col(i) = r.col(i) * c.precision[i];
    root_t += w.col(i).array();
  }
  s.mass += r.colwise().sum().transpose();
  s.mode_weight += w.colwise().sum().transpose();
  s.mode_target.noalias() += w.transpose().lazyProduct(y);
  root_t = root_t.sqrt();
  w = (w.array().colwise() / root_t).matrix();
  root_t_y = root_t * y.array();
  return log_likelihood;
}

// portable_e_step's work on the fastest path: the AVX2 kernel (core/mixture_sweep_avx2.hpp) where
// the CPU and the active path allow it and the modes fit its registers.
double chunk_e_step(const ChunkArray& e, const Eigen::Ref<const Eigen::VectorXd>& y,
                    const ModeConstants& c, EStepScratch& scratch, ChunkRows r, ChunkRows w,
                    ChunkArray root_t, ChunkArray root_t_y, ExactStepSums& s) {
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
  const VectorMathPath path = active_vector_math_path();
  if (path == VectorMathPath::Avx2Fma && vector_math_path_available(path) &&
      c.modes() <= avx2::kSweepMaxModes) {
    const avx2::SweepModes modes{c.modes(), c.log_constant.data(), c.minus_half_precision.data(),
                                 c.precision.data(), c.mean.data()};
    return avx2::sweep_e_step(
        e.data(), y.data(), e.size(), modes,
        {r.data(), r.outerStride(), w.data(), w.outerStride(), root_t.data(), root_t_y.data(),
         s.mass.data(), s.mode_weight.data(), s.mode_target.data()});
  }
#endif
  return portable_e_step(e, y, c, scratch, r, w, root_t, root_t_y, s);
}

}  // namespace

Eigen::RowVectorXd ExactStepSums::weighted_mean() const {
  const double total = mode_weight.sum();
  return centre + (mode_sums.rowwise().sum().transpose() / total);
}

ExactStepSums exact_step_sweep(const Eigen::Ref<const Eigen::MatrixXd>& h,
                               const Eigen::Ref<const Eigen::VectorXd>& y,
                               const Eigen::VectorXd& theta, const MixtureParameters& mixture,
                               const Eigen::RowVectorXd& centre, Eigen::MatrixXd& responsibilities,
                               const ParallelFor& parallel_for) {
  const Eigen::Index k = y.size();
  const Eigen::Index p = h.cols();
  const int m = mixture.modes();
  responsibilities.resize(k, m);
  const ModeConstants constants(mixture);
  const auto zero_sums = [&] {
    ExactStepSums s;
    s.centre = centre;
    s.gram = Eigen::MatrixXd::Zero(p, p);
    s.gram_rhs = Eigen::VectorXd::Zero(p);
    s.mode_sums = Eigen::MatrixXd::Zero(p, m);
    s.mode_weight = Eigen::VectorXd::Zero(m);
    s.mode_target = Eigen::VectorXd::Zero(m);
    s.mass = Eigen::VectorXd::Zero(m);
    return s;
  };
  // Each stripe's sums from zero, in its own working arrays.
  std::vector<ExactStepSums> stripe_sums(static_cast<std::size_t>(stripe_count(k)));
  for_each_stripe(k, parallel_for, [&](int stripe, Eigen::Index begin, Eigen::Index end) {
    ExactStepSums s = zero_sums();
    EStepScratch scratch(m);
    Eigen::ArrayXd residual(kMixtureSweepChunk), root(kMixtureSweepChunk), root_y(kMixtureSweepChunk);
    Eigen::MatrixXd centred(kMixtureSweepChunk, p);
    Eigen::MatrixXd weights(kMixtureSweepChunk, m);
    for (Eigen::Index first = begin; first < end; first += kMixtureSweepChunk) {
      const Eigen::Index n = std::min(kMixtureSweepChunk, end - first);
      const auto h_chunk = h.middleRows(first, n);
      auto e = residual.head(n);
      e = y.segment(first, n).array();
      subtract_product(h_chunk, theta, e.matrix());
      auto r = responsibilities.middleRows(first, n);
      auto w = weights.topRows(n);
      auto root_t = root.head(n);
      auto root_t_y = root_y.head(n);
      s.log_likelihood += chunk_e_step(e, y.segment(first, n), constants, scratch, r, w, root_t,
                                       root_t_y, s);
      // x_k = √t_k (H_k − c) in one pass; then Σ_k w_ki (H_k − c) = xᵀ (w_i / √t), the Gram
      // matrix and its right-hand side xᵀ (√t y) (the chunk is in cache).
      auto x = centred.topRows(n);
      scale_centred_rows(h_chunk, centre, root_t.matrix(), x);
      add_cross_products(x, w, s.mode_sums);
      add_lower_gram(x, s.gram);
      add_cross_products(x, root_t_y.matrix(), s.gram_rhs);
    }
    stripe_sums[static_cast<std::size_t>(stripe)] = std::move(s);
  });
  // Added in stripe order, whatever ran them.
  ExactStepSums s = zero_sums();
  for (const ExactStepSums& part : stripe_sums) {
    s.gram += part.gram;
    s.gram_rhs += part.gram_rhs;
    s.mode_sums += part.mode_sums;
    s.mode_weight += part.mode_weight;
    s.mode_target += part.mode_target;
    s.mass += part.mass;
    s.log_likelihood += part.log_likelihood;
  }
  if (!std::isfinite(s.log_likelihood)) {
    throw NumericalError(
        "mixture log-likelihood is not finite: a residual is not finite or every mode has zero "
        "weight");
  }
  s.gram.triangularView<Eigen::StrictlyUpper>() = s.gram.transpose();
  return s;
}

void exact_step_solve(const Eigen::Ref<const Eigen::MatrixXd>& h,
                      const Eigen::Ref<const Eigen::VectorXd>& y, const ExactStepSums& s,
                      const Eigen::MatrixXd& responsibilities, double floor,
                      Eigen::VectorXd& theta, MixtureParameters& mixture,
                      const ParallelFor& parallel_for) {
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
  std::vector<Eigen::ArrayXd> stripe_square(static_cast<std::size_t>(stripe_count(k)));
  for_each_stripe(k, parallel_for, [&](int stripe, Eigen::Index begin, Eigen::Index end) {
    Eigen::ArrayXd part = Eigen::ArrayXd::Zero(m);
    Eigen::ArrayXd residual(kMixtureSweepChunk);
    for (Eigen::Index first = begin; first < end; first += kMixtureSweepChunk) {
      const Eigen::Index n = std::min(kMixtureSweepChunk, end - first);
      auto e = residual.head(n);
      e = y.segment(first, n).array();
      if (p > 0) subtract_product(h.middleRows(first, n), theta, e.matrix());
      const auto r = responsibilities.middleRows(first, n);
      for (int i = 0; i < m; ++i) part[i] += (r.col(i).array() * (e - mean[i]).square()).sum();
    }
    stripe_square[static_cast<std::size_t>(stripe)] = std::move(part);
  });
  Eigen::ArrayXd square = Eigen::ArrayXd::Zero(m);
  for (const Eigen::ArrayXd& part : stripe_square) square += part;
  mixture.mean = mean;
  mixture.variance = (square / s.mass.array()).max(floor).matrix();
  mixture.weight = s.mass / static_cast<double>(k);
  mixture.weight /= mixture.weight.sum();
}

}  // namespace tofcomp::core
