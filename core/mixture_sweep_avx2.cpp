// Compiled with -mavx2 -mfma (core/CMakeLists.txt). Only <immintrin.h> (static inline intrinsics),
// core/avx2_lanes.hpp (static functions) and this file's own functions: no inline function with
// external linkage (see core/vector_math_avx2.hpp).
#include "core/mixture_sweep_avx2.hpp"

#include "core/avx2_lanes.hpp"

namespace tofcomp::core::avx2 {
namespace {

// Groups of four ranges whose sums of scaled densities are multiplied before one log is taken:
// each sum is in [1, m] (its largest term is 1), so a lane's product stays below
// kSweepMaxModes^kProductGroups = 10^64, far inside a double's range, and the product's rounding
// (one part in 2^53 per factor) moves its log by under 1e-14. One log per 64 ranges instead of
// one per range: the log was the sweep's largest single cost.
constexpr long kProductGroups = 64;
static_assert(kSweepMaxModes <= 10, "a lane's product of kProductGroups sums must stay finite");

// Four ranges: their responsibilities, weights and t into the lanes' registers; the log-sum-exp
// of their joint densities is top + log(sum), returned as its two parts.
inline __attribute__((always_inline)) void four_ranges(__m256d e, const SweepModes& modes,
                                                       __m256d* r, __m256d* w, __m256d& t,
                                                       __m256d& top, __m256d& sum) {
  top = _mm256_set1_pd(-__builtin_inf());
  for (int i = 0; i < modes.m; ++i) {
    const __m256d d = _mm256_sub_pd(e, _mm256_set1_pd(modes.mean[i]));
    r[i] = _mm256_fmadd_pd(_mm256_mul_pd(d, d), _mm256_set1_pd(modes.minus_half_precision[i]),
                           _mm256_set1_pd(modes.log_constant[i]));
    top = _mm256_max_pd(top, r[i]);
  }
  sum = _mm256_setzero_pd();
  for (int i = 0; i < modes.m; ++i) {
    r[i] = _ZGVdN4v_exp(_mm256_sub_pd(r[i], top));
    sum = _mm256_add_pd(sum, r[i]);
  }
  const __m256d inverse = _mm256_div_pd(_mm256_set1_pd(1.0), sum);
  t = _mm256_setzero_pd();
  for (int i = 0; i < modes.m; ++i) {
    r[i] = _mm256_mul_pd(r[i], inverse);
    w[i] = _mm256_mul_pd(r[i], _mm256_set1_pd(modes.precision[i]));
    t = _mm256_add_pd(t, w[i]);
  }
}

}  // namespace

double sweep_e_step(const double* e, const double* y, long n, const SweepModes& modes,
                    const SweepChunkOut& out) {
  __m256d rk[kSweepMaxModes], wk[kSweepMaxModes];
  __m256d mass_sum[kSweepMaxModes], weight_sum[kSweepMaxModes], target_sum[kSweepMaxModes];
  for (int i = 0; i < modes.m; ++i) {
    mass_sum[i] = weight_sum[i] = target_sum[i] = _mm256_setzero_pd();
  }
  // The log-likelihood as Σ top + Σ log(Π sum) over runs of kProductGroups groups.
  __m256d top_total = _mm256_setzero_pd();
  __m256d log_products = _mm256_setzero_pd();
  __m256d product = _mm256_set1_pd(1.0);
  long groups_in_product = 0;
  const auto add_group = [&](__m256d top, __m256d sum) {
    top_total = _mm256_add_pd(top_total, top);
    product = _mm256_mul_pd(product, sum);
    if (++groups_in_product == kProductGroups) {
      log_products = _mm256_add_pd(log_products, _ZGVdN4v_log(product));
      product = _mm256_set1_pd(1.0);
      groups_in_product = 0;
    }
  };
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
    __m256d tk, top, sum;
    four_ranges(_mm256_loadu_pd(e + k), modes, rk, wk, tk, top, sum);
    add_group(top, sum);
    store(k, kLanes, tk, _mm256_loadu_pd(y + k));
  }
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
    __m256d tk, top, sum;
    four_ranges(_mm256_load_pd(e_lanes), modes, rk, wk, tk, top, sum);
    // The padding lanes' r and w are zeroed so that they add nothing to the modes' sums, and
    // their top and sum count as log 1 = 0.
    const __m256d keep = _mm256_cmp_pd(_mm256_set_pd(3.0, 2.0, 1.0, 0.0),
                                       _mm256_set1_pd(static_cast<double>(lanes)), _CMP_LT_OQ);
    add_group(_mm256_and_pd(top, keep), _mm256_blendv_pd(_mm256_set1_pd(1.0), sum, keep));
    for (int i = 0; i < modes.m; ++i) {
      rk[i] = _mm256_and_pd(rk[i], keep);
      wk[i] = _mm256_and_pd(wk[i], keep);
    }
    store(k, lanes, tk, _mm256_load_pd(y_lanes));
  }
  log_products = _mm256_add_pd(log_products, _ZGVdN4v_log(product));
  const double total = horizontal_sum(top_total) + horizontal_sum(log_products);
  for (int i = 0; i < modes.m; ++i) {
    out.mass[i] += horizontal_sum(mass_sum[i]);
    out.mode_weight[i] += horizontal_sum(weight_sum[i]);
    out.mode_target[i] += horizontal_sum(target_sum[i]);
  }
  return total;
}

}  // namespace tofcomp::core::avx2
