#include "core/extended_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/column_products.hpp"
#include "core/error.hpp"
#include "core/vector_math.hpp"

namespace tofcomp::core {
namespace {

constexpr Eigen::Index kChunk = kExtendedSweepChunk;

// Per noise state s and mode i: log π_{s,i} − ½ log(2π σ²_{s,i}), 1/(2σ²_{s,i}) and 1/σ²_{s,i}.
struct StateConstants {
  Eigen::MatrixXd log_constant, half_precision, precision;  // states × M
  explicit StateConstants(const ExtendedMixture& model) {
    const int states = model.states();
    const int m = model.modes.modes();
    log_constant.resize(states, m);
    half_precision.resize(states, m);
    precision.resize(states, m);
    for (int s = 0; s < states; ++s) {
      for (int i = 0; i < m; ++i) {
        const double weight = model.weight(s, i);
        const double variance = model.variance(s, i);
        const double log_weight =
            weight > 0.0 ? std::log(weight) : -std::numeric_limits<double>::infinity();
        log_constant(s, i) = log_weight - 0.5 * std::log(2.0 * std::numbers::pi * variance);
        precision(s, i) = 1.0 / variance;
        half_precision(s, i) = 0.5 * precision(s, i);
      }
    }
  }
};

// A chunk's working arrays.
struct ChunkScratch {
  Eigen::ArrayXd e, top, total, log_total, root_t, root_t_y, inverse_root_t;
  Eigen::ArrayXXd joint;     // n × M: the log joints, then the densities over their largest
  Eigen::MatrixXd weights;   // n × M: w_ki
  Eigen::MatrixXd centred;   // n × p: √t_k (X_k − c)
  Eigen::MatrixXd own;       // n × Σ(1 + q_i): w_ki u_kj / √t_k, mode by mode
  Eigen::MatrixXd shift;     // n × M: Z_ki β_i (no rows when no mode has columns)
  ChunkScratch(Eigen::Index p, int m, Eigen::Index own_columns, bool shifted)
      : e(kChunk), top(kChunk), total(kChunk), log_total(kChunk), root_t(kChunk),
        root_t_y(kChunk), inverse_root_t(kChunk), joint(kChunk, m), weights(kChunk, m),
        centred(kChunk, p), own(kChunk, own_columns), shift(shifted ? kChunk : 0, m) {}
};

}  // namespace

Eigen::RowVectorXd ExtendedStepSums::weighted_mean() const {
  Eigen::RowVectorXd offset = Eigen::RowVectorXd::Zero(centre.size());
  double total = 0.0;
  for (const ModeNormalBlock& b : blocks) {
    offset += b.c.row(0);  // Σ_k w_ki (X_k − c)
    total += b.a(0, 0);    // Σ_k w_ki
  }
  return centre + offset / total;
}

bool extended_sweep_applies(const ExtendedMixture& model) {
  return model.transition.size() == 0 && !(model.outlier_weight > 0.0);
}

ExtendedStepSums extended_step_sweep(const ExtendedDesign& design, const Eigen::VectorXd& y,
                                     const ExtendedParameters& at,
                                     const Eigen::RowVectorXd& centre,
                                     ExtendedResponsibilities& responsibilities) {
  const ExtendedMixture& model = at.model;
  const Eigen::Index k = y.size();
  const Eigen::Index p = design.shared.cols();
  const int m = model.modes.modes();
  const StateConstants constants(model);
  const bool one_state = model.states() == 1;

  // Each mode's own columns u = [1, Z_i] and where they sit among the chunk's `own` columns.
  std::vector<Eigen::Index> own_first(static_cast<std::size_t>(m));
  Eigen::Index own_columns = 0;
  ExtendedStepSums s;
  s.centre = centre;
  s.gram = Eigen::MatrixXd::Zero(p, p);
  s.gram_rhs = Eigen::VectorXd::Zero(p);
  s.blocks.resize(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) {
    const Eigen::Index q = design.mode_columns[static_cast<std::size_t>(i)].cols();
    own_first[static_cast<std::size_t>(i)] = own_columns;
    own_columns += 1 + q;
    ModeNormalBlock& b = s.blocks[static_cast<std::size_t>(i)];
    b.a = Eigen::MatrixXd::Zero(1 + q, 1 + q);
    b.t = Eigen::VectorXd::Zero(1 + q);
  }
  Eigen::MatrixXd own_cross = Eigen::MatrixXd::Zero(p, own_columns);  // Σ_k X̃_kᵀ w_ki u_kj

  responsibilities.mode.resize(k, m);
  responsibilities.outlier = Eigen::VectorXd::Zero(k);
  responsibilities.transitions.resize(0, 0);
  const bool shifted = has_mode_columns(design);
  ChunkScratch c(p, m, own_columns, shifted);
  for (Eigen::Index first = 0; first < k; first += kChunk) {
    const Eigen::Index n = std::min(kChunk, k - first);
    const auto x_chunk = design.shared.middleRows(first, n);
    const auto y_chunk = y.segment(first, n).array();
    const auto state = design.state.segment(first, n);
    auto e = c.e.head(n);
    e = y_chunk;
    subtract_product(x_chunk, at.theta, e.matrix());
    // log π_{s,i} N(e_k; μ_i + Z_ki β_i, σ²_{s,i}) for every mode, at each range's state.
    auto joint = c.joint.topRows(n);
    auto shift = c.shift.topRows(shifted ? n : 0);
    if (shifted) mode_shifts_of_rows(design, at.mode_coefficients, first, n, shift);
    for (int i = 0; i < m; ++i) {
      auto column = joint.col(i);
      column = e - model.modes.mean[i];
      if (shifted) column -= shift.col(i).array();
      if (one_state) {
        column = constants.log_constant(0, i) - column.square() * constants.half_precision(0, i);
      } else {
        for (Eigen::Index r = 0; r < n; ++r) {
          const int st = state[r];
          column[r] = constants.log_constant(st, i) -
                      column[r] * column[r] * constants.half_precision(st, i);
        }
      }
    }
    // Responsibilities by log-sum-exp; the chunk's log-likelihood Σ_k (top_k + log Σ_i e^…).
    auto top = c.top.head(n);
    top = joint.rowwise().maxCoeff();
    for (int i = 0; i < m; ++i) {
      joint.col(i) -= top;
      exp_in_place(joint.col(i));
    }
    auto total = c.total.head(n);
    total = joint.rowwise().sum();
    auto log_total = c.log_total.head(n);
    log_total = total;
    log_in_place(log_total);
    s.log_likelihood += (top + log_total).sum();
    total = total.inverse();
    auto r = responsibilities.mode.middleRows(first, n);
    auto w = c.weights.topRows(n);
    for (int i = 0; i < m; ++i) {
      r.col(i) = (joint.col(i) * total).matrix();
      if (one_state) {
        w.col(i) = r.col(i) * constants.precision(0, i);
      } else {
        for (Eigen::Index row = 0; row < n; ++row) {
          w(row, i) = r(row, i) * constants.precision(state[row], i);
        }
      }
    }
    // The normal equations' sums: x = √t (X − c), Σ t X̃ᵀX̃ = xᵀx, Σ t X̃ᵀ y = xᵀ(√t y), and
    // Σ w_ki u_kj X̃_k = xᵀ (w_ki u_kj / √t_k).
    auto root_t = c.root_t.head(n);
    root_t = w.rowwise().sum().array().sqrt();
    auto x = c.centred.topRows(n);
    scale_centred_rows(x_chunk, centre, root_t.matrix(), x);
    add_lower_gram(x, s.gram);
    auto root_t_y = c.root_t_y.head(n);
    root_t_y = root_t * y_chunk;
    add_cross_products(x, root_t_y.matrix(), s.gram_rhs);
    auto own = c.own.topRows(n);
    auto inverse_root_t = c.inverse_root_t.head(n);
    inverse_root_t = root_t.inverse();
    for (int i = 0; i < m; ++i) {
      const auto& z = design.mode_columns[static_cast<std::size_t>(i)];
      const Eigen::Index at_column = own_first[static_cast<std::size_t>(i)];
      ModeNormalBlock& b = s.blocks[static_cast<std::size_t>(i)];
      const auto w_i = w.col(i).array();
      own.col(at_column) = (w_i * inverse_root_t).matrix();
      b.a(0, 0) += w_i.sum();
      b.t[0] += (w_i * y_chunk).sum();
      for (Eigen::Index j = 0; j < z.cols(); ++j) {
        const auto z_j = z.col(j).segment(first, n).array();
        own.col(at_column + 1 + j) = (w_i * z_j * inverse_root_t).matrix();
        b.a(1 + j, 0) += (w_i * z_j).sum();
        b.t[1 + j] += (w_i * z_j * y_chunk).sum();
        for (Eigen::Index l = 0; l <= j; ++l) {
          b.a(1 + j, 1 + l) += (w_i * z_j * z.col(l).segment(first, n).array()).sum();
        }
      }
    }
    add_cross_products(x, own, own_cross);
  }
  if (!std::isfinite(s.log_likelihood)) {
    throw NumericalError(
        "extended EM: the log-likelihood is not finite (a range with zero probability under "
        "every mode)");
  }
  s.gram.triangularView<Eigen::StrictlyUpper>() = s.gram.transpose();
  for (int i = 0; i < m; ++i) {
    ModeNormalBlock& b = s.blocks[static_cast<std::size_t>(i)];
    b.a.triangularView<Eigen::StrictlyUpper>() = b.a.transpose();
    b.c = own_cross.middleCols(own_first[static_cast<std::size_t>(i)], b.a.rows()).transpose();
  }
  return s;
}

}  // namespace tofcomp::core
