// Eq. 8 extended by what the residual diagnosis found (core/residual_diagnosis.hpp):
//   y_k = d + H(t^j_k) θ + γ c_k + w_k,   w_k from the extended noise (core/extended_mixture.hpp),
// where c_k is a covariate the bias lacks: the time since the start of the data (time drift) or
// the junction's heating rate (heating hysteresis). The covariate is one more column of the
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
  TimeHours,             // hours since the start of the data (the daemon: since its start)
  HeatingRateCPerMinute  // dt^j/dt in °C/min, from the junction estimate
};

const char* covariate_name(Covariate covariate);

struct ModelExtension {
  EffectKind effect = EffectKind::SerialDependence;  // the effect it models
  Covariate covariate = Covariate::None;
  double covariate_mm = 0.0;  // γ: mm per unit of the covariate
  ExtendedMixture noise;      // replaces the paper's mixture

  // Throws InvalidInput when the noise is invalid or a covariate has a non-finite γ.
  void validate() const;
  // γ c_k for each range (zeros without a covariate).
  Eigen::VectorXd covariate_bias(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                 const Eigen::Ref<const Eigen::VectorXd>& junction_c) const;
};

// The covariate at each range: hours since time_s[0]'s origin (time_s / 3600), or the junction's
// rate of change in °C/min by local least-squares slopes over ±30 s.
Eigen::VectorXd covariate_values(Covariate covariate,
                                 const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                 const Eigen::Ref<const Eigen::VectorXd>& junction_c);

inline constexpr double kHeatingRateHalfWindowS = 30.0;

}  // namespace tofcomp::core
