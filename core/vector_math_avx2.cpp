// Compiled with -mavx2 -mfma (core/CMakeLists.txt). Only <immintrin.h> (static inline intrinsics),
// core/avx2_lanes.hpp (static functions) and this file's own functions: no inline function with
// external linkage (see core/vector_math_avx2.hpp).
#include "core/vector_math_avx2.hpp"

#include "core/avx2_lanes.hpp"

namespace tofcomp::core::avx2 {
namespace {

// f over x[0..n), four at a time; the last n mod 4 through a buffer padded with `pad` (a value
// f takes without a floating-point exception).
template <__m256d (*f)(__m256d)>
inline __attribute__((always_inline)) void apply(double* x, long n, double pad) {
  long i = 0;
  for (; i + kLanes <= n; i += kLanes) _mm256_storeu_pd(x + i, f(_mm256_loadu_pd(x + i)));
  if (i == n) return;
  alignas(32) double tail[kLanes] = {pad, pad, pad, pad};
  for (long j = 0; i + j < n; ++j) tail[j] = x[i + j];
  _mm256_store_pd(tail, f(_mm256_load_pd(tail)));
  for (long j = 0; i + j < n; ++j) x[i + j] = tail[j];
}

}  // namespace

void exp_in_place(double* x, long n) { apply<_ZGVdN4v_exp>(x, n, 0.0); }
void log_in_place(double* x, long n) { apply<_ZGVdN4v_log>(x, n, 1.0); }
void erfc_in_place(double* x, long n) { apply<_ZGVdN4v_erfc>(x, n, 0.0); }

}  // namespace tofcomp::core::avx2
