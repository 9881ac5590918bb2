// The warm-up transient after a power-on, a covariate the paper's model (Eq. 8) lacks:
// c_k = exp(−t_on,k / τ), t_on the time since the scanner was last switched on. It is not the
// junction's heating (Eq. 3 models that) but what settles besides: the laser driver, the
// receiver. τ is not known in advance: the diagnosis tests, and the extension fits, each τ of
// a fixed logarithmic grid (core/residual_diagnosis.hpp, calibration/model_extension.hpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace tofcomp::core {

inline constexpr std::array<double, 7> kWarmUpTimeConstantsS{30.0,  60.0,  120.0, 240.0,
                                                            480.0, 960.0, 1920.0};

// exp(−t_on / τ) at one instant.
inline double warm_up_covariate(double time_since_power_on_s, double time_constant_s) {
  return std::exp(-time_since_power_on_s / time_constant_s);
}

// exp(−t_on / τ) at each range.
inline Eigen::VectorXd warm_up_covariate(
    const Eigen::Ref<const Eigen::VectorXd>& time_since_power_on_s, double time_constant_s) {
  return time_since_power_on_s.unaryExpr(
      [&](double t) { return warm_up_covariate(t, time_constant_s); });
}

// One column per time constant of the grid.
inline Eigen::MatrixXd warm_up_covariates(
    const Eigen::Ref<const Eigen::VectorXd>& time_since_power_on_s) {
  Eigen::MatrixXd out(time_since_power_on_s.size(),
                      static_cast<Eigen::Index>(kWarmUpTimeConstantsS.size()));
  for (std::size_t i = 0; i < kWarmUpTimeConstantsS.size(); ++i) {
    out.col(static_cast<Eigen::Index>(i)) =
        warm_up_covariate(time_since_power_on_s, kWarmUpTimeConstantsS[i]);
  }
  return out;
}

}  // namespace tofcomp::core
