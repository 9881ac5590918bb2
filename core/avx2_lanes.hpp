// What the AVX2 + FMA translation units (core/*_avx2.cpp, compiled with -mavx2 -mfma) share:
// glibc's libmvec kernels and a register's horizontal sum. Included only by them: every function
// here has internal linkage (static), so none can stand in for portable code (see
// core/vector_math_avx2.hpp).
#pragma once

#include <immintrin.h>

// glibc's libmvec, AVX2 variants (x86_64 vector function ABI: 4 doubles in a ymm register).
extern "C" __m256d _ZGVdN4v_exp(__m256d x);
extern "C" __m256d _ZGVdN4v_log(__m256d x);
extern "C" __m256d _ZGVdN4v_erfc(__m256d x);

namespace tofcomp::core::avx2 {

// Doubles per ymm register.
static constexpr long kLanes = 4;

// The sum of a register's four doubles.
static inline __attribute__((always_inline)) double horizontal_sum(__m256d v) {
  const __m128d pair = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(pair, _mm_unpackhi_pd(pair, pair)));
}

}  // namespace tofcomp::core::avx2
