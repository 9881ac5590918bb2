// The products over a chunk of ranges that the exact EM step of §5 sums (core/mixture_sweep.cpp):
// the lower triangle of XᵀX, XᵀZ, e − Hθ and the centred, scaled rows of H, on column-major blocks (columns contiguous, any
// leading dimension). With p basis columns and M modes they are K·(p² / 2 + p·M + p)
// multiply-adds per sweep: beyond a few columns, most of an EM iteration. Two paths, chosen as
// core/vector_math.hpp chooses (the same VectorMathPath):
//   - Portable: Eigen's products at the build's instruction set (SSE2 by default);
//   - Avx2Fma: core/column_products_avx2.cpp, compiled for AVX2 and FMA and holding no inline
//     function with external linkage (as core/vector_math_avx2.cpp): four ranges per register,
//     four columns per pass over the other column, multiply and add fused.
// They add in different orders, so they agree to rounding, not bit for bit
// (tests/core/column_products_test.cpp).
#pragma once

#include <Eigen/Core>

#include "core/vector_math.hpp"

namespace tofcomp::core {

// gram(i, j) += Σ_k x(k, i) x(k, j) for i ≥ j (the lower triangle; the rest is not touched).
// gram is p × p, p = x.cols().
void add_lower_gram(const Eigen::Ref<const Eigen::MatrixXd>& x, Eigen::Ref<Eigen::MatrixXd> gram,
                    VectorMathPath path = active_vector_math_path());

// out(i, j) += Σ_k x(k, i) z(k, j): out is x.cols() × z.cols(); x and z have the same rows.
void add_cross_products(const Eigen::Ref<const Eigen::MatrixXd>& x,
                        const Eigen::Ref<const Eigen::MatrixXd>& z,
                        Eigen::Ref<Eigen::MatrixXd> out,
                        VectorMathPath path = active_vector_math_path());

// x(k, i) = (h(k, i) − c_i) · s_k: H's rows centred on c and scaled (x is h's size).
void scale_centred_rows(const Eigen::Ref<const Eigen::MatrixXd>& h,
                        const Eigen::Ref<const Eigen::RowVectorXd>& centre,
                        const Eigen::Ref<const Eigen::VectorXd>& scale,
                        Eigen::Ref<Eigen::MatrixXd> x,
                        VectorMathPath path = active_vector_math_path());

// e(k) −= Σ_i h(k, i) θ_i: the residual of Eq. 8's bias.
void subtract_product(const Eigen::Ref<const Eigen::MatrixXd>& h,
                      const Eigen::Ref<const Eigen::VectorXd>& theta,
                      Eigen::Ref<Eigen::VectorXd> e,
                      VectorMathPath path = active_vector_math_path());

}  // namespace tofcomp::core
