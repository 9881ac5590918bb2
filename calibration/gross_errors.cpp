#include "calibration/gross_errors.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/extended_mixture.hpp"

namespace tofcomp::calibration {

namespace {

// The outlier density's span is at least this (mm): the device's resolution.
constexpr double kMinimumOutlierSpanMm = kRangeResolutionMm;
// The outlier weight's EM (the modes held): at most this many steps, stopped when it moves less
// than the tolerance; never above a half (more would not be outliers, as core/extended_em.cpp
// bounds it) nor below the gross errors' share (each of them is an outlier by the device's scale).
constexpr int kOutlierWeightIterations = 500;
constexpr double kOutlierWeightTolerance = 1e-10;
constexpr double kMaximumOutlierWeight = 0.5;

}  // namespace

GrossErrors find_gross_errors(const MeasuredData& data) {
  data.require_true_ranges();
  GrossErrors out;
  out.ranges = data.range_mm.size();
  out.kept.reserve(static_cast<std::size_t>(out.ranges));
  for (Eigen::Index k = 0; k < out.ranges; ++k) {
    if (std::abs(data.range_mm[k] - data.true_range_mm[k]) > kGrossErrorMm) {
      ++out.count;
    } else {
      out.kept.push_back(k);
    }
  }
  if (2 * out.count >= out.ranges) {
    // Most ranges this far from the reference distance: the distance is wrong, not the ranges.
    // Nothing is set apart, and the calibration's plausibility (calibration/plausibility.hpp)
    // names the error it predicts.
    out.count = 0;
    out.kept.resize(static_cast<std::size_t>(out.ranges));
    std::iota(out.kept.begin(), out.kept.end(), Eigen::Index{0});
  }
  return out;
}

std::string gross_errors_note(const GrossErrors& gross) {
  return fmt::format(
      "{} of {} ranges ({:.2f} %) are gross errors, more than {:g} mm from the true distance "
      "(beyond any lasing mode): left out of Eq. 8's fit and carried as an outlier component",
      gross.count, gross.ranges, 100.0 * gross.share(), kGrossErrorMm);
}

double fit_outlier_weight(const Eigen::Ref<const Eigen::VectorXd>& residual_mm,
                          const core::ExtendedMixture& start) {
  core::ExtendedMixture model = start;
  const Eigen::VectorXi state = Eigen::VectorXi::Zero(residual_mm.size());
  core::ExtendedResponsibilities r;
  for (int i = 0; i < kOutlierWeightIterations; ++i) {
    core::extended_e_step(residual_mm, state, Eigen::MatrixXd(), model, r);
    const double next = std::clamp(r.outlier.mean(), start.outlier_weight, kMaximumOutlierWeight);
    const double step = std::abs(next - model.outlier_weight);
    model.outlier_weight = next;
    if (step < kOutlierWeightTolerance) break;
  }
  return model.outlier_weight;
}

std::optional<core::ModelExtension> gross_error_extension(
    const core::MixtureParameters& modes, double share,
    const Eigen::Ref<const Eigen::VectorXd>& residual_mm) {
  if (!(share > 0.0)) return std::nullopt;
  core::ModelExtension e;
  e.effects.push_back({core::Parameter::Outliers, core::Covariate::None});
  e.extended_mixture = core::without_extensions(modes);
  e.extended_mixture.outlier_weight = share;
  e.extended_mixture.outlier_density =
      1.0 / std::max(residual_mm.maxCoeff() - residual_mm.minCoeff(), kMinimumOutlierSpanMm);
  e.extended_mixture.outlier_weight = fit_outlier_weight(residual_mm, e.extended_mixture);
  e.validate();
  return e;
}

}  // namespace tofcomp::calibration
