// Element-wise exp, log and erfc over arrays of doubles, the cost that dominates the E-steps of
// Eq. 18 (a log-sum-exp per range) and the scoring of rounded ranges (an erfc per range and mode). Two paths compute them:
//   - Portable: Eigen's vectorized exp and log at the build's instruction set (SSE2 by default),
//     std::erfc;
//   - Avx2Fma: glibc's vector math library (libmvec, its AVX2 kernels, 4 doubles at a time,
//     within 4 ulp), in a translation unit of its own compiled for AVX2 and FMA and holding no
//     inline function with external linkage (no Eigen, no standard-library template), so that
//     no AVX2 code can stand in for the portable path's (core/vector_math_avx2.cpp).
// The fastest path the CPU runs is chosen once, at run time (__builtin_cpu_supports), so the
// default portable build runs AVX2 where the CPU has it and SSE2 elsewhere. Both paths agree to a
// few ulp per element (tests/core/vector_math_test.cpp).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <type_traits>

namespace tofcomp::core {

enum class VectorMathPath { Portable, Avx2Fma };

// Whether this build and this CPU can run `path` (Portable: always).
bool vector_math_path_available(VectorMathPath path);
// Avx2Fma when available, else Portable; decided once.
VectorMathPath fastest_vector_math_path();
const char* vector_math_path_name(VectorMathPath path);
// The path the functions below take by default: the fastest, unless one is pinned (by a test or
// a benchmark comparing the two; std::nullopt unpins). Process-wide.
VectorMathPath active_vector_math_path();
void pin_vector_math_path(std::optional<VectorMathPath> path);

// x[0..n) ← exp(x[0..n)), log(x[0..n)), erfc(x[0..n)) on `path` (an unavailable path runs
// Portable). Special values as std::exp, std::log and std::erfc (log(0) = −∞, NaN stays NaN),
// but for underflow: exp(−∞) and exp(x < −708) are 0, or on Eigen's SSE2 path a subnormal below
// the smallest normal double.
void exp_in_place(double* x, Eigen::Index n, VectorMathPath path = active_vector_math_path());
void log_in_place(double* x, Eigen::Index n, VectorMathPath path = active_vector_math_path());
void erfc_in_place(double* x, Eigen::Index n, VectorMathPath path = active_vector_math_path());

// On an Eigen array or vector expression with contiguous storage (a column of a column-major
// array, a segment of a vector).
template <typename Dense>
void exp_in_place(Dense&& x, VectorMathPath path = active_vector_math_path()) {
  static_assert(std::remove_reference_t<Dense>::InnerStrideAtCompileTime == 1);
  exp_in_place(x.data(), x.size(), path);
}
template <typename Dense>
void log_in_place(Dense&& x, VectorMathPath path = active_vector_math_path()) {
  static_assert(std::remove_reference_t<Dense>::InnerStrideAtCompileTime == 1);
  log_in_place(x.data(), x.size(), path);
}
template <typename Dense>
void erfc_in_place(Dense&& x, VectorMathPath path = active_vector_math_path()) {
  static_assert(std::remove_reference_t<Dense>::InnerStrideAtCompileTime == 1);
  erfc_in_place(x.data(), x.size(), path);
}

}  // namespace tofcomp::core
