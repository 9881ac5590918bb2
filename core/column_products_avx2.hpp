// The AVX2 + FMA kernels of core/column_products.hpp on raw column-major arrays (ld: the distance
// between columns). Internal to core/column_products.cpp; defined in core/column_products_avx2.cpp
// (compiled with -mavx2 -mfma), which includes no Eigen header and no project header but
// core/avx2_lanes.hpp, for the reason core/vector_math_avx2.hpp gives. Call only on a CPU with AVX2
// and FMA.
#pragma once

namespace tofcomp::core::avx2 {

void add_lower_gram(const double* x, long n, long p, long ldx, double* gram, long ldg);
void add_cross_products(const double* x, long n, long p, long ldx, const double* z, long q,
                        long ldz, double* out, long ldo);
void scale_centred_rows(const double* h, long n, long p, long ldh, const double* centre,
                        const double* scale, double* x, long ldx);
void subtract_product(const double* h, long n, long p, long ldh, const double* theta, double* e);

}  // namespace tofcomp::core::avx2
