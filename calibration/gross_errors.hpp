// Gross errors in a record with a known distance: ranges farther from it than any lasing mode
// of an LMS 200 reaches (a spurious return from dust, an edge or another surface; a corrupted
// reading). Eq. 8 describes the lasing modes; a cluster of spurious returns a metre beyond the
// target, fitted as one more "mode", would be a mode no laser has (the plausibility gate of
// calibration/plausibility.hpp refuses a mode beyond ±50 mm) and, fitted by the paper's modes
// alone, drags them metres. Training fits Eq. 8 on the other ranges and carries the gross
// errors as the outlier component of the extended mixture (core/extended_mixture.hpp), its
// weight fitted from their share, so that compensation weighs such a range as any outlier.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "calibration/plausibility.hpp"
#include "core/lms200_limits.hpp"
#include "core/model_extension.hpp"

namespace tofcomp::calibration {

// A range is a gross error when its error y − d exceeds the largest range error a plausible
// calibration predicts (μ_i + H(t)θ within ±kMaxRangeErrorMm) by this many of the device's
// statistical errors: 50 + 6 × 5 = 80 mm. A lasing mode's range lies so far out with a
// probability of about 1e-9 even at that edge.
inline constexpr double kGrossErrorStatisticalErrors = 6.0;
inline constexpr double kGrossErrorMm =
    kMaxRangeErrorMm + kGrossErrorStatisticalErrors * core::lms200::kStatisticalErrorMm;

struct GrossErrors {
  std::vector<Eigen::Index> kept;  // the other ranges, in time order
  Eigen::Index count = 0;          // ranges with |y − d| > kGrossErrorMm
  Eigen::Index ranges = 0;         // all the ranges
  double share() const { return ranges > 0 ? static_cast<double>(count) / ranges : 0.0; }
};

// None when half the ranges or more are that far: then the reference distance is wrong, not the
// ranges. Throws core::InvalidInput when a range has no true distance.
GrossErrors find_gross_errors(const MeasuredData& data);

// "N of K ranges (x %) are gross errors, ...": what training says of them.
std::string gross_errors_note(const GrossErrors& gross);

// The outlier weight ε of `start` (its modes and outlier density held) by EM on the residuals:
// ε ← the mean of P(outlier | e_k) to its fixed point, from start.outlier_weight, never below it.
// The gross errors' share is where it starts: ranges of the spurious process that fall within
// 80 mm, among the lasing modes' ranges, raise it.
double fit_outlier_weight(const Eigen::Ref<const Eigen::VectorXd>& residual_mm,
                          const core::ExtendedMixture& start);

// The extension that carries the gross errors: the outlier component uniform over the span of the
// residuals y − d − H(t)θ of every range (at least 1 mm), its weight fitted from `share` on them
// (fit_outlier_weight), the modes as trained on the other ranges. None when share is 0.
std::optional<core::ModelExtension> gross_error_extension(
    const core::MixtureParameters& modes, double share,
    const Eigen::Ref<const Eigen::VectorXd>& residual_mm);

}  // namespace tofcomp::calibration
