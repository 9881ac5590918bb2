// Eq. 8 extended by what the residual diagnosis found (core/residual_diagnosis.hpp):
//   y_k = d + H(t^j_k) θ + γ c_k + w_k,   w_k from the extended mixture
//   (core/extended_mixture.hpp),
// where c_k is a covariate the bias lacks: the time since the start of the data (time drift),
// the junction's heating rate (heating hysteresis) or the warm-up transient exp(−t_on/τ) after
// a power-on (core/warm_up.hpp). The covariate is one more column of the
// design, so training and testing keep the closed forms of §5-§6. What a calibration file stores
// next to the paper's model, and what the offline tools and the daemon apply.
#pragma once

#include <Eigen/Core>
#include <string>

#include "core/extended_mixture.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::core {

enum class Covariate {
  None,
  TimeHours,              // hours since the start of the data (the daemon: since its start)
  HeatingRateCPerMinute,  // dt^j/dt in °C/min, from the junction estimate
  WarmUp                  // exp(−t_on/τ), t_on the seconds since the last power-on
};

// What the covariates are computed from, at each range.
struct CovariateInputs {
  Eigen::Ref<const Eigen::VectorXd> time_s;
  Eigen::Ref<const Eigen::VectorXd> junction_c;
  Eigen::Ref<const Eigen::VectorXd> time_since_power_on_s;
};

const char* covariate_name(Covariate covariate);

struct ModelExtension {
  EffectKind effect = EffectKind::SerialDependence;  // the effect it models
  Covariate covariate = Covariate::None;
  double covariate_mm = 0.0;         // γ: mm per unit of the covariate
  double time_constant_s = 0.0;      // τ of the warm-up covariate (0 for the others)
  ExtendedMixture extended_mixture;  // replaces the paper's mixture (model.mixture)

  // Throws InvalidInput when the extended mixture is invalid, a covariate has a non-finite γ or the
  // warm-up a time constant that is not positive.
  void validate() const;
  // c_k for each range (zeros without a covariate).
  Eigen::VectorXd covariate_values(const CovariateInputs& in) const;
  // γ c_k for each range.
  Eigen::VectorXd covariate_bias(const CovariateInputs& in) const;
  // γ c at one instant (the daemon's scan): time_s for time drift, the junction's heating rate in
  // °C/min, the seconds since the last power-on.
  double covariate_bias_at(double time_s, double heating_rate_c_per_min,
                           double time_since_power_on_s) const;
};

// The covariate at each range: hours since time_s's origin (time_s / 3600), the junction's rate
// of change in °C/min by local least-squares slopes over ±30 s, or exp(−t_on/τ).
Eigen::VectorXd covariate_values(Covariate covariate, const CovariateInputs& in,
                                 double time_constant_s = 0.0);

inline constexpr double kHeatingRateHalfWindowS = 30.0;

}  // namespace tofcomp::core
