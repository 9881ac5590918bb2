#include "core/mode_regression.hpp"

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

}  // namespace tofcomp::core
