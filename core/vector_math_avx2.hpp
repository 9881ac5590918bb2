// The AVX2 + FMA kernels of core/vector_math.hpp, on raw arrays. Internal to core/vector_math.cpp;
// defined in core/vector_math_avx2.cpp (compiled with -mavx2 -mfma), which must not include Eigen's
// headers or this project's (but core/avx2_lanes.hpp, whose functions are static): any inline
// function with external linkage compiled there could be the one the linker keeps for the
// portable code too.
#pragma once

namespace tofcomp::core::avx2 {

// x[0..n) ← exp(x[0..n)), log(x[0..n)), erfc(x[0..n)). Call only on a CPU with AVX2 and FMA.
void exp_in_place(double* x, long n);
void log_in_place(double* x, long n);
void erfc_in_place(double* x, long n);

}  // namespace tofcomp::core::avx2
