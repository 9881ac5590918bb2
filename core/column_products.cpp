#include "core/column_products.hpp"

#if defined(TOFCOMP_VECTOR_MATH_AVX2)
#include "core/column_products_avx2.hpp"
#endif

namespace tofcomp::core {
namespace {

#if defined(TOFCOMP_VECTOR_MATH_AVX2)
bool runs_avx2(VectorMathPath path) {
  return path == VectorMathPath::Avx2Fma && vector_math_path_available(path);
}
#endif

}  // namespace

void add_lower_gram(const Eigen::Ref<const Eigen::MatrixXd>& x, Eigen::Ref<Eigen::MatrixXd> gram,
                    VectorMathPath path) {
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
  if (runs_avx2(path)) {
    avx2::add_lower_gram(x.data(), x.rows(), x.cols(), x.outerStride(), gram.data(),
                         gram.outerStride());
    return;
  }
#endif
  (void)path;
  // Column j's rows j .. p − 1 as one product (Eigen vectorizes it over the ranges).
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    const Eigen::Index below = x.cols() - j;
    gram.col(j).tail(below).noalias() += x.rightCols(below).transpose() * x.col(j);
  }
}

void add_cross_products(const Eigen::Ref<const Eigen::MatrixXd>& x,
                        const Eigen::Ref<const Eigen::MatrixXd>& z,
                        Eigen::Ref<Eigen::MatrixXd> out, VectorMathPath path) {
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
  if (runs_avx2(path)) {
    avx2::add_cross_products(x.data(), x.rows(), x.cols(), x.outerStride(), z.data(), z.cols(),
                             z.outerStride(), out.data(), out.outerStride());
    return;
  }
#endif
  (void)path;
  out.noalias() += x.transpose() * z;
}

void scale_centred_rows(const Eigen::Ref<const Eigen::MatrixXd>& h,
                        const Eigen::Ref<const Eigen::RowVectorXd>& centre,
                        const Eigen::Ref<const Eigen::VectorXd>& scale,
                        Eigen::Ref<Eigen::MatrixXd> x, VectorMathPath path) {
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
  if (runs_avx2(path)) {
    avx2::scale_centred_rows(h.data(), h.rows(), h.cols(), h.outerStride(), centre.data(),
                             scale.data(), x.data(), x.outerStride());
    return;
  }
#endif
  (void)path;
  x = (h.rowwise() - centre).array().colwise() * scale.array();
}

void subtract_product(const Eigen::Ref<const Eigen::MatrixXd>& h,
                      const Eigen::Ref<const Eigen::VectorXd>& theta,
                      Eigen::Ref<Eigen::VectorXd> e, VectorMathPath path) {
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
  if (runs_avx2(path)) {
    avx2::subtract_product(h.data(), h.rows(), h.cols(), h.outerStride(), theta.data(), e.data());
    return;
  }
#endif
  (void)path;
  e.noalias() -= h * theta;
}

}  // namespace tofcomp::core
