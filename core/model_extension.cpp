#include "core/model_extension.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

const char* covariate_name(Covariate covariate) {
  switch (covariate) {
    case Covariate::None:
      return "none";
    case Covariate::TimeHours:
      return "time_h";
    case Covariate::HeatingRateCPerMinute:
      return "heating_rate_c_per_min";
  }
  return "unknown";
}

void ModelExtension::validate() const {
  noise.validate();
  if (!std::isfinite(covariate_mm)) throw InvalidInput("the covariate coefficient is not finite");
}

Eigen::VectorXd covariate_values(Covariate covariate,
                                 const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                 const Eigen::Ref<const Eigen::VectorXd>& junction_c) {
  require_same_length(time_s.size(), "time", junction_c.size(), "junction temperature");
  switch (covariate) {
    case Covariate::None:
      return Eigen::VectorXd::Zero(time_s.size());
    case Covariate::TimeHours:
      return time_s / 3600.0;
    case Covariate::HeatingRateCPerMinute:
      return 60.0 * local_rate(time_s, junction_c, kHeatingRateHalfWindowS);
  }
  throw InvalidInput("unknown covariate");
}

Eigen::VectorXd ModelExtension::covariate_bias(
    const Eigen::Ref<const Eigen::VectorXd>& time_s,
    const Eigen::Ref<const Eigen::VectorXd>& junction_c) const {
  return covariate_mm * covariate_values(covariate, time_s, junction_c);
}

}  // namespace tofcomp::core
