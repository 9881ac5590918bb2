// The (θ, μ) block of the exact M-step of §5 (Eq. 19 solved jointly): minimizes
//   Σ_k Σ_i w_ki (ỹ_k − H_k θ − μ_i)²,   w_ki = r_ki / σ²_ki,
// over θ and the mode offsets μ_1..μ_M at once. The μ are profiled out of the normal equations
// and H is centred on its weighted mean first, so the reduced p × p system
//   (G − Σ_i h_i h_iᵀ / s_i) θ = b − Σ_i h_i c_i / s_i
// stays well conditioned. Shared by the paper's EM (core/em_train.hpp) and the extended EM
// (core/extended_em.hpp), whose weights differ only in where σ²_ki comes from.
// Cost O(K·p² + K·M·p); never a K × K matrix.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace tofcomp::core {

struct BiasAndOffsets {
  Eigen::VectorXd theta;  // θ (p)
  Eigen::VectorXd mean;   // μ_i (M)
};

// h: K × p, y: K, weights: K × M non-negative with every column summing to a positive mass.
// Throws NumericalError when the reduced normal matrix is singular.
BiasAndOffsets solve_bias_and_offsets(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                      const Eigen::Ref<const Eigen::VectorXd>& y,
                                      const Eigen::Ref<const Eigen::MatrixXd>& weights,
                                      Eigen::MatrixXd& scratch);

// The same block when some modes' offsets move with covariates (the grammar's mode-offset terms,
// core/effect_grammar.hpp): minimizes
//   Σ_k Σ_i w_ki (ỹ_k − X_k θ − μ_i − Z_ki β_i)²
// over θ, every μ_i and every β_i at once, Z_i the K × q_i columns of mode i (q_i may be 0). Each
// mode's block (μ_i, β_i) is profiled out of the normal equations through its small
// (1 + q_i)² system, leaving the p × p system for θ, with X centred as above.
struct MeanStructure {
  Eigen::VectorXd theta;                        // θ (p)
  Eigen::VectorXd mean;                         // μ_i (M)
  std::vector<Eigen::VectorXd> mode_coefficients;  // β_i (q_i each)
};

// x: K × p (p may be 0), mode_columns: M matrices of K rows (or 0 × 0 for none), y: K,
// weights: K × M. Throws NumericalError when a system is singular.
MeanStructure solve_mean_structure(const Eigen::Ref<const Eigen::MatrixXd>& x,
                                   const std::vector<Eigen::MatrixXd>& mode_columns,
                                   const Eigen::Ref<const Eigen::VectorXd>& y,
                                   const Eigen::Ref<const Eigen::MatrixXd>& weights,
                                   Eigen::MatrixXd& scratch);

// The same solution from the normal equations' sums, X centred on any row c (a sweep that sums
// them as it goes, core/extended_sweep.hpp): with t_k = Σ_i w_ki, X̃_k = X_k − c and mode i's
// own columns u_k = [1, Z_ki],
//   gram = Σ_k t_k X̃_kᵀ X̃_k (p × p),  gram_rhs = Σ_k t_k X̃_kᵀ y_k (p),
//   per mode a = Σ_k w_ki u_kᵀ u_k,  c = Σ_k w_ki u_kᵀ X̃_k,  t = Σ_k w_ki u_kᵀ y_k.
struct ModeNormalBlock {
  Eigen::MatrixXd a;  // (1 + q) × (1 + q)
  Eigen::MatrixXd c;  // (1 + q) × p
  Eigen::VectorXd t;  // 1 + q
};
MeanStructure solve_mean_structure(Eigen::MatrixXd gram, Eigen::VectorXd gram_rhs,
                                   const Eigen::RowVectorXd& centre,
                                   const std::vector<ModeNormalBlock>& blocks);

}  // namespace tofcomp::core
