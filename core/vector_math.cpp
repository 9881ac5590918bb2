#include "core/vector_math.hpp"

#include <atomic>
#include <cmath>

#if defined(TOFCOMP_VECTOR_MATH_AVX2)
#include "core/vector_math_avx2.hpp"
#endif

namespace tofcomp::core {
namespace {

bool cpu_has_avx2_fma() {
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

// −1: none pinned; else the pinned VectorMathPath.
std::atomic<int> pinned_path{-1};

using Kernel = void (*)(double*, long);
#if defined(TOFCOMP_VECTOR_MATH_AVX2)
constexpr Kernel kAvx2Exp = avx2::exp_in_place;
constexpr Kernel kAvx2Log = avx2::log_in_place;
constexpr Kernel kAvx2Erfc = avx2::erfc_in_place;
#else
constexpr Kernel kAvx2Exp = nullptr;
constexpr Kernel kAvx2Log = nullptr;
constexpr Kernel kAvx2Erfc = nullptr;
#endif

// x ← f(x) by the AVX2 kernel when `path` asks for it and can run, else by the portable one.
template <typename Portable>
void run(double* x, Eigen::Index n, VectorMathPath path, Kernel avx2_kernel,
         const Portable& portable) {
  if (avx2_kernel != nullptr && path == VectorMathPath::Avx2Fma &&
      vector_math_path_available(path)) {
    avx2_kernel(x, static_cast<long>(n));
  } else {
    portable(Eigen::Map<Eigen::ArrayXd>(x, n));
  }
}

}  // namespace

bool vector_math_path_available(VectorMathPath path) {
  static const bool avx2_fma = cpu_has_avx2_fma();
  return path == VectorMathPath::Portable || avx2_fma;
}

VectorMathPath fastest_vector_math_path() {
  static const VectorMathPath fastest = vector_math_path_available(VectorMathPath::Avx2Fma)
                                            ? VectorMathPath::Avx2Fma
                                            : VectorMathPath::Portable;
  return fastest;
}

VectorMathPath active_vector_math_path() {
  const int pinned = pinned_path.load(std::memory_order_relaxed);
  return pinned < 0 ? fastest_vector_math_path() : static_cast<VectorMathPath>(pinned);
}

void pin_vector_math_path(std::optional<VectorMathPath> path) {
  pinned_path.store(path ? static_cast<int>(*path) : -1, std::memory_order_relaxed);
}

const char* vector_math_path_name(VectorMathPath path) {
  return path == VectorMathPath::Avx2Fma ? "AVX2+FMA (libmvec)" : "portable (Eigen)";
}

void exp_in_place(double* x, Eigen::Index n, VectorMathPath path) {
  run(x, n, path, kAvx2Exp, [](Eigen::Map<Eigen::ArrayXd> a) { a = a.exp(); });
}

void log_in_place(double* x, Eigen::Index n, VectorMathPath path) {
  run(x, n, path, kAvx2Log, [](Eigen::Map<Eigen::ArrayXd> a) { a = a.log(); });
}

void erfc_in_place(double* x, Eigen::Index n, VectorMathPath path) {
  run(x, n, path, kAvx2Erfc, [](Eigen::Map<Eigen::ArrayXd> a) {
    for (double& v : a) v = std::erfc(v);
  });
}

}  // namespace tofcomp::core
