// The recalibration gate's checks: see plausibility.hpp.
#include "calibration/plausibility.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace tofcomp::calibration {

namespace {

// The thermal network (Eq. 2) as physics: its time constants and steady rises within their
// bounds. Written so that NaN fails every test.
void thermal_implausibilities(const core::ThermalParameters& p, std::vector<std::string>& faults) {
  // A rise is above 0: the smallest positive double is its lower bound.
  constexpr double kAboveZero = std::numeric_limits<double>::min();
  const struct {
    const char* what;
    double value;
    double low;
    double high;
    const char* unit;
  } quantities[] = {
      {"time constant R1·C1 (junction over case)", p.r1_k_per_w * p.c1_j_per_k,
       kMinThermalTimeConstantS, kMaxThermalTimeConstantS, "s"},
      {"time constant R2·C2 (case over ambient)", p.r2_k_per_w * p.c2_j_per_k,
       kMinThermalTimeConstantS, kMaxThermalTimeConstantS, "s"},
      {"steady rise P·R1 (junction over case)", p.power_w * p.r1_k_per_w, kAboveZero,
       kMaxThermalRiseK, "K"},
      {"steady rise P·R2 (case over ambient)", p.power_w * p.r2_k_per_w, kAboveZero,
       kMaxThermalRiseK, "K"},
  };
  for (const auto& [what, value, low, high, unit] : quantities) {
    if (value >= low && value <= high) continue;
    faults.push_back(fmt::format(
        "its thermal {} is {:g} {}, outside {:g} to {:g} {} (thermal r1_k_per_w {:g}, "
        "c1_j_per_k {:g}, r2_k_per_w {:g}, c2_j_per_k {:g}, power_w {:g})",
        what, value, unit, low == kAboveZero ? 0.0 : low, high, unit, p.r1_k_per_w,
        p.c1_j_per_k, p.r2_k_per_w, p.c2_j_per_k, p.power_w));
  }
}

}  // namespace

std::vector<std::string> implausibilities(const core::Calibration& calibration) {
  std::vector<std::string> faults;
  thermal_implausibilities(calibration.thermal, faults);
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
  // The basis's scaling as training makes it (core::TemperatureScaling::spanning): a half range
  // below its floor scales every temperature but its centre to a number beyond any basis (a
  // half_range_c of 1e-300 made every bias NaN).
  const core::TemperatureScaling& scaling = model.basis.scaling();
  if (!(scaling.half_range_c >= core::kMinScalingHalfRangeC &&
        scaling.half_range_c <= kMaxJunctionC - kMinJunctionC &&
        scaling.center_c >= kMinJunctionC && scaling.center_c <= kMaxJunctionC)) {
    faults.push_back(fmt::format(
        "its basis is scaled about {:g} °C by a half range of {:g} °C, outside {:g} to {:g} °C "
        "about a centre within {:.0f} to {:.0f} °C",
        scaling.center_c, scaling.half_range_c, core::kMinScalingHalfRangeC,
        kMaxJunctionC - kMinJunctionC, kMinJunctionC, kMaxJunctionC));
    return faults;
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
