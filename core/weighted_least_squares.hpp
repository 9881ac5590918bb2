// The linear algebra behind the M-steps of Eq. 19 and Eq. 23: weighted normal equations solved
// with equilibration and a pivoted LDLᵀ factorization whose conditioning is checked, so a
// singular HᵀC⁻¹H (too few distinct temperatures for the basis, end of §5) is a clear error and
// never a NaN. Never forms a K × K matrix: C is diagonal and is kept as a K-vector of weights.
#pragma once

#include <Eigen/Core>
#include <string_view>

namespace tofcomp::core {

// Reciprocal condition number (of the equilibrated matrix) below which a system is singular.
inline constexpr double kSingularReciprocalCondition = 1e-13;

// SᵀS (p × p) for a K × p matrix S, in O(K·p²) time (a symmetric rank-K update).
Eigen::MatrixXd gram(const Eigen::Ref<const Eigen::MatrixXd>& s);

// Hᵀ diag(w) H (p × p) in O(K·p²) time, through a scratch K × p buffer holding diag(√w) H.
Eigen::MatrixXd weighted_gram(const Eigen::Ref<const Eigen::MatrixXd>& h,
                              const Eigen::Ref<const Eigen::VectorXd>& weights,
                              Eigen::MatrixXd& scratch);

// Solves G x = b for a symmetric positive semi-definite G. Throws NumericalError naming `what`
// when G is singular to working precision.
Eigen::VectorXd solve_normal_equations(const Eigen::Ref<const Eigen::MatrixXd>& gram,
                                       const Eigen::Ref<const Eigen::VectorXd>& rhs,
                                       std::string_view what);

}  // namespace tofcomp::core
