// One sweep over the ranges for the exact EM step of §5: the E-step of Eq. 18 (responsibilities
// by log-sum-exp and the log-likelihood Σ_k log δ_k) fused with the weighted sums the exact
// M-step's (θ, μ) block needs (core/mode_regression.hpp's normal equations, weights
// w_ki = r_ki / σ_i²), then the closed-form σ_i² and π_i of Eq. 19 in a second, light sweep at
// the new (θ, μ). Ranges are taken in chunks that stay in cache. On a CPU with AVX2 and FMA (the
// path core/vector_math.hpp chooses) a chunk's E-step runs as one kernel, four ranges per register
// from the residual to the responsibilities, the weights and the modes' sums
// (core/mixture_sweep_avx2.cpp), and the products over the basis columns as
// core/column_products.hpp's; elsewhere Eigen's array code does both. The ranges are cut into
// fixed stripes of chunks, each summed from zero and the stripes added in order: with a
// ParallelFor the stripes run on the caller's threads and the answer is the serial one bit for
// bit. Internal to core/em_train.cpp.
#pragma once

#include <Eigen/Core>

#include "core/gaussian_mixture.hpp"
#include "core/parallel_for.hpp"

namespace tofcomp::core {

// The sums of one sweep, H centred on a fixed row c (any c gives the same answer; one near the
// weighted mean of H keeps the reduced normal matrix well conditioned):
struct ExactStepSums {
  Eigen::RowVectorXd centre;    // c (p)
  Eigen::MatrixXd gram;         // Σ_k t_k (H_k − c)ᵀ(H_k − c), t_k = Σ_i w_ki   (p × p)
  Eigen::VectorXd gram_rhs;     // Σ_k t_k (H_k − c)ᵀ y_k                        (p)
  Eigen::MatrixXd mode_sums;    // Σ_k w_ki (H_k − c)ᵀ                           (p × M)
  Eigen::VectorXd mode_weight;  // Σ_k w_ki                                      (M)
  Eigen::VectorXd mode_target;  // Σ_k w_ki y_k                                  (M)
  Eigen::VectorXd mass;         // Σ_k r_ki                                      (M)
  double log_likelihood = 0.0;
  // The t-weighted mean of H: a good centre for the next sweep.
  Eigen::RowVectorXd weighted_mean() const;
};

// The E-step at (θ, mixture) fused with the sums above. Fills responsibilities (K × M).
// Throws NumericalError when the log-likelihood is not finite.
ExactStepSums exact_step_sweep(const Eigen::Ref<const Eigen::MatrixXd>& h,
                               const Eigen::Ref<const Eigen::VectorXd>& y,
                               const Eigen::VectorXd& theta, const MixtureParameters& mixture,
                               const Eigen::RowVectorXd& centre, Eigen::MatrixXd& responsibilities,
                               const ParallelFor& parallel_for = {});

// The exact M-step from a sweep's sums (Eq. 19 solved exactly, an ECM step): θ and μ by the
// reduced normal equations, then σ_i² (at least floor) and π_i in closed form at the new (θ, μ)
// from the responsibilities, in one more sweep. Throws NumericalError when the normal matrix is
// singular.
void exact_step_solve(const Eigen::Ref<const Eigen::MatrixXd>& h,
                      const Eigen::Ref<const Eigen::VectorXd>& y, const ExactStepSums& sums,
                      const Eigen::MatrixXd& responsibilities, double floor,
                      Eigen::VectorXd& theta, MixtureParameters& mixture,
                      const ParallelFor& parallel_for = {});

}  // namespace tofcomp::core
