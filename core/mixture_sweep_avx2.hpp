// The E-step part of the exact sweep (core/mixture_sweep.cpp) for one chunk of ranges on AVX2 +
// FMA. Internal to core/mixture_sweep.cpp; defined in core/mixture_sweep_avx2.cpp (compiled with
// -mavx2 -mfma), which includes no Eigen header and no project header but core/avx2_lanes.hpp, for
// the reason core/vector_math_avx2.hpp gives. Call only on a CPU with AVX2 and FMA.
#pragma once

namespace tofcomp::core::avx2 {

// The most modes the kernel takes: one register of log densities per mode.
inline constexpr int kSweepMaxModes = 10;

// The modes' constants, m of each: log π_i − ½ log(2π σ_i²), −1/(2σ_i²), 1/σ_i², μ_i.
struct SweepModes {
  int m;
  const double* log_constant;
  const double* minus_half_precision;
  const double* precision;
  const double* mean;
};

// For the n residuals e and ranges y of a chunk (Eq. 18): r(k, i) the responsibilities (column i
// at r + i·ldr); with the exact step's weights w_ki = r_ki / σ_i² and t_k = Σ_i w_ki, the scaled
// forms its products take: scaled_w(k, i) = w_ki / √t_k (column i at scaled_w + i·ldw),
// root_t[k] = √t_k, root_t_y[k] = √t_k y_k. Adds Σ_k r_ki to mass[i], Σ_k w_ki to
// mode_weight[i], Σ_k w_ki y_k to mode_target[i]; returns Σ_k log Σ_i π_i N(e_k; μ_i, σ_i²).
// m ≤ kSweepMaxModes.
struct SweepChunkOut {
  double* r;
  long ldr;
  double* scaled_w;
  long ldw;
  double* root_t;
  double* root_t_y;
  double* mass;
  double* mode_weight;
  double* mode_target;
};
double sweep_e_step(const double* e, const double* y, long n, const SweepModes& modes,
                    const SweepChunkOut& out);

}  // namespace tofcomp::core::avx2
