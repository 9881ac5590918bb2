#include "core/model_extension.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/validation.hpp"
#include "core/warm_up.hpp"

namespace tofcomp::core {

const char* covariate_name(Covariate covariate) {
  switch (covariate) {
    case Covariate::None:
      return "none";
    case Covariate::TimeHours:
      return "time_h";
    case Covariate::HeatingRateCPerMinute:
      return "heating_rate_c_per_min";
    case Covariate::WarmUp:
      return "warm_up";
  }
  return "unknown";
}

void ModelExtension::validate() const {
  extended_mixture.validate();
  if (!std::isfinite(covariate_mm)) throw InvalidInput("the covariate coefficient is not finite");
  if (covariate == Covariate::WarmUp &&
      !(time_constant_s > 0.0 && std::isfinite(time_constant_s))) {
    throw InvalidInput("the warm-up covariate needs a positive time constant");
  }
}

Eigen::VectorXd covariate_values(Covariate covariate, const CovariateInputs& in,
                                 double time_constant_s) {
  const Eigen::Index n = in.time_s.size();
  require_same_length(n, "time", in.junction_c.size(), "junction temperature");
  require_same_length(n, "time", in.time_since_power_on_s.size(), "time since power-on");
  switch (covariate) {
    case Covariate::None:
      return Eigen::VectorXd::Zero(n);
    case Covariate::TimeHours:
      return in.time_s / 3600.0;
    case Covariate::HeatingRateCPerMinute:
      return 60.0 * local_rate(in.time_s, in.junction_c, kHeatingRateHalfWindowS);
    case Covariate::WarmUp:
      require_positive(time_constant_s, "warm-up time constant");
      return warm_up_covariate(in.time_since_power_on_s, time_constant_s);
  }
  throw InvalidInput("unknown covariate");
}

Eigen::VectorXd ModelExtension::covariate_values(const CovariateInputs& in) const {
  return core::covariate_values(covariate, in, time_constant_s);
}

Eigen::VectorXd ModelExtension::covariate_bias(const CovariateInputs& in) const {
  return covariate_mm * covariate_values(in);
}

double ModelExtension::covariate_bias_at(double time_s, double heating_rate_c_per_min,
                                         double time_since_power_on_s) const {
  switch (covariate) {
    case Covariate::None:
      return 0.0;
    case Covariate::TimeHours:
      return covariate_mm * (time_s / 3600.0);
    case Covariate::HeatingRateCPerMinute:
      return covariate_mm * heating_rate_c_per_min;
    case Covariate::WarmUp:
      return covariate_mm * warm_up_covariate(time_since_power_on_s, time_constant_s);
  }
  return 0.0;
}

}  // namespace tofcomp::core
