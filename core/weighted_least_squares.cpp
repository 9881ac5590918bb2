#include "core/weighted_least_squares.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::core {

Eigen::MatrixXd gram(const Eigen::Ref<const Eigen::MatrixXd>& s) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(s.cols(), s.cols());
  g.selfadjointView<Eigen::Lower>().rankUpdate(s.transpose());
  g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
  return g;
}

Eigen::MatrixXd weighted_gram(const Eigen::Ref<const Eigen::MatrixXd>& h,
                              const Eigen::Ref<const Eigen::VectorXd>& weights,
                              Eigen::MatrixXd& scratch) {
  scratch = weights.array().sqrt().matrix().asDiagonal() * h;
  return gram(scratch);
}

Eigen::VectorXd solve_normal_equations(const Eigen::Ref<const Eigen::MatrixXd>& gram,
                                       const Eigen::Ref<const Eigen::VectorXd>& rhs,
                                       std::string_view what) {
  const Eigen::Index p = gram.rows();
  // Jacobi equilibration: S G S with S = diag(1/√G_jj) has a unit diagonal, so the condition
  // estimate measures the basis, not the units of its columns.
  Eigen::VectorXd scale(p);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double diagonal = gram(j, j);
    if (!(diagonal > 0.0) || !std::isfinite(diagonal)) {
      std::ostringstream msg;
      msg << what << " is singular: column " << j + 1
          << " of the basis carries no weight on these data (it is zero wherever the weights are "
             "not); use fewer basis columns or data spanning more temperatures";
      throw NumericalError(msg.str());
    }
    scale[j] = 1.0 / std::sqrt(diagonal);
  }
  const Eigen::MatrixXd scaled = scale.asDiagonal() * gram * scale.asDiagonal();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(scaled);
  // The pivots of the equilibrated LDLᵀ bound the conditioning from below; rcond() estimates
  // it from the inverse. Either one failing means the columns are dependent.
  const Eigen::VectorXd pivots = ldlt.vectorD();
  const double pivot_ratio =
      ldlt.info() == Eigen::Success ? pivots.minCoeff() / pivots.cwiseAbs().maxCoeff() : 0.0;
  const double rcond = ldlt.info() == Eigen::Success ? ldlt.rcond() : 0.0;
  if (!(pivot_ratio > kSingularReciprocalCondition) || !(rcond > kSingularReciprocalCondition)) {
    std::ostringstream msg;
    // A negative pivot (an indefinite matrix, from rounding) is a reciprocal condition of 0.
    msg << what << " is singular to working precision (reciprocal condition "
        << std::max(0.0, std::min(rcond, pivot_ratio)) << "): the data do not determine the " << p
        << " basis coefficients; use fewer basis columns or data spanning more distinct "
           "temperatures (paper, end of §5)";
    throw NumericalError(msg.str());
  }
  Eigen::VectorXd x = scale.asDiagonal() * ldlt.solve(scale.asDiagonal() * rhs);
  if (!x.allFinite()) {
    throw NumericalError(std::string(what) + " gave a non-finite solution");
  }
  return x;
}

}  // namespace tofcomp::core
