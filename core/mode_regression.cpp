#include "core/mode_regression.hpp"

#include <Eigen/Cholesky>
#include <string>

#include "core/error.hpp"
#include "core/weighted_least_squares.hpp"

namespace tofcomp::core {

BiasAndOffsets solve_bias_and_offsets(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                      const Eigen::Ref<const Eigen::VectorXd>& y,
                                      const Eigen::Ref<const Eigen::MatrixXd>& w,
                                      Eigen::MatrixXd& scratch) {
  if (h.cols() == 0) {  // no bias columns: the offsets are the weighted means
    const Eigen::VectorXd mass = w.colwise().sum().transpose();
    return {Eigen::VectorXd(0), ((w.transpose() * y).array() / mass.array()).matrix()};
  }
  const Eigen::VectorXd total_weight = w.rowwise().sum();
  const Eigen::ArrayXd sqrt_weight = total_weight.array().sqrt();
  const Eigen::RowVectorXd column_mean = (total_weight.transpose() * h) / total_weight.sum();

  scratch = sqrt_weight.matrix().asDiagonal() * (h.rowwise() - column_mean);
  Eigen::MatrixXd g = gram(scratch);
  Eigen::VectorXd b = scratch.transpose() * (sqrt_weight * y.array()).matrix();
  // h_i = Σ_k w_ki (H_k − H̄): the scratch rows are √(Σ_i w_ki)(H_k − H̄).
  const Eigen::ArrayXd inverse_sqrt_weight = (sqrt_weight > 0.0).select(sqrt_weight.inverse(), 0.0);
  const Eigen::MatrixXd mode_sums =
      scratch.transpose() * (w.array().colwise() * inverse_sqrt_weight).matrix();  // p × M
  const Eigen::VectorXd mode_mass = w.colwise().sum().transpose();                 // s_i
  const Eigen::VectorXd mode_target = w.transpose() * y;                           // c_i
  for (Eigen::Index i = 0; i < w.cols(); ++i) {
    g.noalias() -= mode_sums.col(i) * mode_sums.col(i).transpose() / mode_mass[i];
    b.noalias() -= mode_sums.col(i) * (mode_target[i] / mode_mass[i]);
  }

  BiasAndOffsets out;
  out.theta = solve_normal_equations(g, b, "the weighted normal matrix HᵀC⁻¹H of the M-step");
  const double centred_bias = column_mean.dot(out.theta);
  out.mean =
      ((mode_target - mode_sums.transpose() * out.theta).array() / mode_mass.array()).matrix();
  out.mean.array() -= centred_bias;
  return out;
}

MeanStructure solve_mean_structure(const Eigen::Ref<const Eigen::MatrixXd>& x,
                                   const std::vector<Eigen::MatrixXd>& mode_columns,
                                   const Eigen::Ref<const Eigen::VectorXd>& y,
                                   const Eigen::Ref<const Eigen::MatrixXd>& w,
                                   Eigen::MatrixXd& scratch) {
  const Eigen::Index k = y.size();
  const Eigen::Index p = x.cols();
  const auto modes = static_cast<std::size_t>(w.cols());
  if (mode_columns.size() != modes) {
    throw InvalidInput("the mean structure needs one (maybe empty) column block per mode");
  }
  bool any_columns = false;
  for (const auto& z : mode_columns) {
    if (z.size() > 0 && z.rows() != k) throw InvalidInput("a mode's columns need one row per range");
    any_columns = any_columns || z.size() > 0;
  }
  MeanStructure out;
  if (!any_columns) {
    BiasAndOffsets plain = solve_bias_and_offsets(x, y, w, scratch);
    out.theta = std::move(plain.theta);
    out.mean = std::move(plain.mean);
    out.mode_coefficients.assign(modes, Eigen::VectorXd(0));
    return out;
  }
  const Eigen::VectorXd total_weight = w.rowwise().sum();
  const Eigen::RowVectorXd column_mean =
      p > 0 ? Eigen::RowVectorXd((total_weight.transpose() * x) / total_weight.sum())
            : Eigen::RowVectorXd(0);
  const Eigen::ArrayXd sqrt_weight = total_weight.array().sqrt();
  scratch = sqrt_weight.matrix().asDiagonal() * (x.rowwise() - column_mean);
  Eigen::MatrixXd g = gram(scratch);
  Eigen::VectorXd b = scratch.transpose() * (sqrt_weight * y.array()).matrix();
  // The scratch rows are √t_k (X_k − X̄), so Σ_k v_k (X_k − X̄) = scratchᵀ (v / √t): no centred
  // copy of X is needed.
  const Eigen::ArrayXd inverse_sqrt_weight = (sqrt_weight > 0.0).select(sqrt_weight.inverse(), 0.0);

  // Mode i's own design [1, Z_i] and the blocks of its normal equations.
  std::vector<ModeNormalBlock> blocks(modes);
  for (std::size_t i = 0; i < modes; ++i) {
    const Eigen::Index q = mode_columns[i].cols();
    const auto w_i = w.col(static_cast<Eigen::Index>(i));
    ModeNormalBlock& blk = blocks[i];
    if (q == 0) {  // the offset alone: sums of the weights
      blk.a = Eigen::MatrixXd::Constant(1, 1, w_i.sum());
      blk.t = Eigen::VectorXd::Constant(1, w_i.dot(y));
      blk.c = p > 0 ? Eigen::MatrixXd((scratch.transpose() *
                                       (w_i.array() * inverse_sqrt_weight).matrix()).transpose())
                    : Eigen::MatrixXd(1, 0);
    } else {
      Eigen::MatrixXd own(k, 1 + q);
      own.col(0).setOnes();
      own.rightCols(q) = mode_columns[i];
      const Eigen::MatrixXd weighted = own.array().colwise() * w_i.array();
      blk.a = weighted.transpose() * own;
      blk.t = weighted.transpose() * y;
      blk.c = p > 0 ? Eigen::MatrixXd(
                          (weighted.array().colwise() * inverse_sqrt_weight).matrix().transpose() *
                          scratch)
                    : Eigen::MatrixXd(1 + q, 0);
    }
  }
  return solve_mean_structure(std::move(g), std::move(b), column_mean, blocks);
}

MeanStructure solve_mean_structure(Eigen::MatrixXd g, Eigen::VectorXd b,
                                   const Eigen::RowVectorXd& centre,
                                   const std::vector<ModeNormalBlock>& blocks) {
  const Eigen::Index p = g.rows();
  const std::size_t modes = blocks.size();
  // Each mode's block (μ_i, β_i) profiled out: G − Σ_i cᵢᵀ aᵢ⁻¹ cᵢ, b − Σ_i cᵢᵀ aᵢ⁻¹ tᵢ.
  if (p > 0) {
    for (std::size_t i = 0; i < modes; ++i) {
      const ModeNormalBlock& blk = blocks[i];
      const Eigen::LDLT<Eigen::MatrixXd> factor(blk.a);
      if (factor.info() != Eigen::Success || !(factor.rcond() >= kSingularReciprocalCondition)) {
        throw NumericalError("the M-step: mode " + std::to_string(i + 1) +
                             "'s offset and covariate columns are singular (a covariate constant "
                             "where the mode has ranges)");
      }
      const Eigen::MatrixXd a_inverse_c = factor.solve(blk.c);
      const Eigen::VectorXd a_inverse_t = factor.solve(blk.t);
      g.noalias() -= blk.c.transpose() * a_inverse_c;
      b.noalias() -= blk.c.transpose() * a_inverse_t;
    }
  }
  MeanStructure out;
  out.theta = p > 0 ? solve_normal_equations(
                          g, b, "the weighted normal matrix of the M-step's bias and offsets")
                    : Eigen::VectorXd(0);
  const double centred_bias = p > 0 ? centre.dot(out.theta) : 0.0;
  out.mean.resize(static_cast<Eigen::Index>(modes));
  out.mode_coefficients.resize(modes);
  for (std::size_t i = 0; i < modes; ++i) {
    const ModeNormalBlock& blk = blocks[i];
    const Eigen::VectorXd rhs = p > 0 ? Eigen::VectorXd(blk.t - blk.c * out.theta) : blk.t;
    const Eigen::VectorXd phi =
        solve_normal_equations(blk.a, rhs, "a mode's offset and its covariate columns");
    out.mean[static_cast<Eigen::Index>(i)] = phi[0] - centred_bias;
    out.mode_coefficients[i] = phi.tail(phi.size() - 1);
  }
  return out;
}

}  // namespace tofcomp::core
