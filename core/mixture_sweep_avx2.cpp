// Compiled with -mavx2 -mfma (core/CMakeLists.txt). Only <immintrin.h> (static inline intrinsics),
// core/avx2_lanes.hpp (static functions) and this file's own functions: no inline function with
// external linkage (see core/vector_math_avx2.hpp).
#include "core/mixture_sweep_avx2.hpp"

#include "core/avx2_lanes.hpp"

namespace tofcomp::core::avx2 {
namespace {

// Four ranges: their responsibilities, weights and t into the lanes' registers; the log-sum-exp
// of their joint densities returned.
inline __attribute__((always_inline)) __m256d four_ranges(__m256d e, const SweepModes& modes,
                                                          __m256d* r, __m256d* w, __m256d& t) {
  __m256d top = _mm256_set1_pd(-__builtin_inf());
  for (int i = 0; i < modes.m; ++i) {
    const __m256d d = _mm256_sub_pd(e, _mm256_set1_pd(modes.mean[i]));
    r[i] = _mm256_fmadd_pd(_mm256_mul_pd(d, d), _mm256_set1_pd(modes.minus_half_precision[i]),
                           _mm256_set1_pd(modes.log_constant[i]));
    top = _mm256_max_pd(top, r[i]);
  }
  __m256d sum = _mm256_setzero_pd();
  for (int i = 0; i < modes.m; ++i) {
    r[i] = _ZGVdN4v_exp(_mm256_sub_pd(r[i], top));
    sum = _mm256_add_pd(sum, r[i]);
  }
  const __m256d log_likelihood = _mm256_add_pd(top, _ZGVdN4v_log(sum));
  const __m256d inverse = _mm256_div_pd(_mm256_set1_pd(1.0), sum);
  t = _mm256_setzero_pd();
  for (int i = 0; i < modes.m; ++i) {
    r[i] = _mm256_mul_pd(r[i], inverse);
    w[i] = _mm256_mul_pd(r[i], _mm256_set1_pd(modes.precision[i]));
    t = _mm256_add_pd(t, w[i]);
  }
  return log_likelihood;
}

}  // namespace

double sweep_e_step(const double* e, const double* y, long n, const SweepModes& modes,
                    const SweepChunkOut& out) {
  __m256d rk[kSweepMaxModes], wk[kSweepMaxModes];
  __m256d mass_sum[kSweepMaxModes], weight_sum[kSweepMaxModes], target_sum[kSweepMaxModes];
  for (int i = 0; i < modes.m; ++i) {
    mass_sum[i] = weight_sum[i] = target_sum[i] = _mm256_setzero_pd();
  }
  __m256d log_likelihood = _mm256_setzero_pd();
  // Four ranges' outputs to memory (`lanes` of them real; all four outside the tail).
  const auto store = [&](long k, long lanes, __m256d tk, __m256d yk) {
    const __m256d root = _mm256_sqrt_pd(tk);
    const __m256d inverse_root = _mm256_div_pd(_mm256_set1_pd(1.0), root);
    alignas(32) double buffer[kLanes];
    const auto put = [&](double* to, __m256d v) {
      if (lanes == kLanes) {
        _mm256_storeu_pd(to, v);
        return;
      }
      _mm256_store_pd(buffer, v);
      for (long j = 0; j < lanes; ++j) to[j] = buffer[j];
    };
    put(out.root_t + k, root);
    put(out.root_t_y + k, _mm256_mul_pd(root, yk));
    for (int i = 0; i < modes.m; ++i) {
      put(out.r + i * out.ldr + k, rk[i]);
      put(out.scaled_w + i * out.ldw + k, _mm256_mul_pd(wk[i], inverse_root));
      mass_sum[i] = _mm256_add_pd(mass_sum[i], rk[i]);
      weight_sum[i] = _mm256_add_pd(weight_sum[i], wk[i]);
      target_sum[i] = _mm256_fmadd_pd(wk[i], yk, target_sum[i]);
    }
  };
  long k = 0;
  for (; k + kLanes <= n; k += kLanes) {
    __m256d tk;
    log_likelihood =
        _mm256_add_pd(log_likelihood, four_ranges(_mm256_loadu_pd(e + k), modes, rk, wk, tk));
    store(k, kLanes, tk, _mm256_loadu_pd(y + k));
  }
  double total = horizontal_sum(log_likelihood);
  if (k < n) {
    // The last n mod 4 ranges in padded lanes (residual and range 0: finite densities); only the
    // real lanes are stored and counted.
    const long lanes = n - k;
    alignas(32) double e_lanes[kLanes] = {0.0, 0.0, 0.0, 0.0};
    alignas(32) double y_lanes[kLanes] = {0.0, 0.0, 0.0, 0.0};
    for (long j = 0; j < lanes; ++j) {
      e_lanes[j] = e[k + j];
      y_lanes[j] = y[k + j];
    }
    __m256d tk;
    alignas(32) double ll[kLanes];
    _mm256_store_pd(ll, four_ranges(_mm256_load_pd(e_lanes), modes, rk, wk, tk));
    for (long j = 0; j < lanes; ++j) total += ll[j];
    // The padding lanes' r and w are zeroed so that they add nothing to the modes' sums.
    const __m256d keep = _mm256_cmp_pd(_mm256_set_pd(3.0, 2.0, 1.0, 0.0),
                                       _mm256_set1_pd(static_cast<double>(lanes)), _CMP_LT_OQ);
    for (int i = 0; i < modes.m; ++i) {
      rk[i] = _mm256_and_pd(rk[i], keep);
      wk[i] = _mm256_and_pd(wk[i], keep);
    }
    store(k, lanes, tk, _mm256_load_pd(y_lanes));
  }
  for (int i = 0; i < modes.m; ++i) {
    out.mass[i] += horizontal_sum(mass_sum[i]);
    out.mode_weight[i] += horizontal_sum(weight_sum[i]);
    out.mode_target[i] += horizontal_sum(target_sum[i]);
  }
  return total;
}

}  // namespace tofcomp::core::avx2
