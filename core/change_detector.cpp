#include "core/change_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

ChangeDetector::ChangeDetector(ChangeDetectorOptions options) : options_(options) {
  require_positive(options_.threshold, "change detector threshold");
  if (!(options_.drift >= 0.0) || !std::isfinite(options_.drift)) {
    throw InvalidInput("change detector drift must be a non-negative number");
  }
}

void ChangeDetector::reset() {
  upper_ = 0.0;
  lower_ = 0.0;
}

bool ChangeDetector::update(double residual, const MixtureParameters& mixture) {
  require_finite(residual, "change detector residual");
  // The most probable mode for this residual (the E-step of Eq. 22 for one sample), then the
  // residual standardized within it.
  int best = 0;
  double best_log = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < mixture.modes(); ++i) {
    const double e = residual - mixture.mean[i];
    const double log_density = std::log(mixture.weight[i]) - 0.5 * std::log(mixture.variance[i]) -
                               0.5 * e * e / mixture.variance[i];
    if (log_density > best_log) {
      best_log = log_density;
      best = i;
    }
  }
  return update_standardized((residual - mixture.mean[best]) / std::sqrt(mixture.variance[best]));
}

bool ChangeDetector::update_standardized(double z) {
  require_finite(z, "change detector residual");
  upper_ = std::max(0.0, upper_ + z - options_.drift);
  lower_ = std::max(0.0, lower_ - z - options_.drift);
  if (upper_ > options_.threshold || lower_ > options_.threshold) {
    reset();
    return true;
  }
  return false;
}

}  // namespace tofcomp::core
