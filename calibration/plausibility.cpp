// The recalibration gate's checks: see plausibility.hpp.
#include "calibration/plausibility.hpp"

#include <fmt/format.h>

#include <cmath>

namespace tofcomp::calibration {

std::vector<std::string> implausibilities(const core::Calibration& calibration) {
  std::vector<std::string> faults;
  const core::MeasurementModel& model = calibration.model;
  const core::MixtureParameters& mixture = model.mixture;
  for (Eigen::Index i = 0; i < mixture.mean.size(); ++i) {
    const double spread = std::sqrt(mixture.variance[i]);
    if (!std::isfinite(spread) || spread > kMaxModeSpreadMm) {
      faults.push_back(fmt::format(
          "mode {}'s standard deviation is {:.1f} mm, more than the {:.0f} mm an LMS 200's "
          "ranges spread (its statistical error is {:.0f} mm)",
          i, spread, kMaxModeSpreadMm, core::lms200::kStatisticalErrorMm));
    }
  }
  if (mixture.mean.size() > 0) {
    const double separation = mixture.mean.maxCoeff() - mixture.mean.minCoeff();
    if (!std::isfinite(separation) || separation > kMaxModeSeparationMm) {
      faults.push_back(
          fmt::format("the modes lie {:.1f} mm apart, more than the {:.0f} mm of an "
                      "LMS 200's lasing modes",
                      separation, kMaxModeSeparationMm));
    }
  }
  // The trained junction temperatures, or without them the basis's own scaling.
  core::TemperatureRange range{model.basis.scaling().center_c - model.basis.scaling().half_range_c,
                               model.basis.scaling().center_c + model.basis.scaling().half_range_c};
  if (model.trained_junction_c) range = *model.trained_junction_c;
  if (!std::isfinite(range.min_c) || !std::isfinite(range.max_c) || range.min_c < kMinJunctionC ||
      range.max_c > kMaxJunctionC || range.min_c > range.max_c) {
    faults.push_back(fmt::format(
        "the trained junction temperatures {:.1f} to {:.1f} °C lie outside {:.0f} to {:.0f} °C",
        range.min_c, range.max_c, kMinJunctionC, kMaxJunctionC));
    return faults;
  }
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(kBiasCheckPoints, range.min_c, range.max_c);
  const Eigen::VectorXd bias = model.bias(t);
  double worst = 0.0;
  Eigen::Index worst_mode = 0;
  Eigen::Index worst_t = 0;
  for (Eigen::Index i = 0; i < mixture.mean.size(); ++i) {
    for (Eigen::Index k = 0; k < t.size(); ++k) {
      const double error = mixture.mean[i] + bias[k];
      if (!std::isfinite(error) || std::abs(error) > std::abs(worst) || !std::isfinite(worst)) {
        worst = error;
        worst_mode = i;
        worst_t = k;
      }
    }
  }
  if (!std::isfinite(worst) || std::abs(worst) > kMaxRangeErrorMm) {
    faults.push_back(fmt::format(
        "in mode {} at {:.2f} °C it predicts a range error of {:+.1f} mm, beyond the ±{:.0f} mm "
        "an LMS 200's can be (its systematic error is ±{:.0f} mm): is the recording's "
        "true_range_mm right?",
        worst_mode, t[worst_t], worst, kMaxRangeErrorMm, core::lms200::kSystematicErrorMm));
  }
  return faults;
}

std::optional<std::string> held_out_regression(const HeldOutComparison& c) {
  const double allowed = c.running_mae_mm * (1.0 + kHeldOutMarginFraction) + kHeldOutMarginMm;
  if (std::isfinite(c.new_mae_mm) && c.new_mae_mm <= allowed) return std::nullopt;
  return fmt::format(
      "on the {} held-out ranges ({} windows) its d̂ errs by {:.3f} mm on average, the running "
      "calibration's by {:.3f} mm: more than {:.0f} % + {:.2f} mm worse",
      c.ranges, c.windows, c.new_mae_mm, c.running_mae_mm, 100.0 * kHeldOutMarginFraction,
      kHeldOutMarginMm);
}

}  // namespace tofcomp::calibration
