// The residuals of a record with a known distance under a calibration that may carry the model
// search's terms (core/model_extension.hpp), as the figures of those terms show them
// (cli/search_figure_data.hpp): the whole record, each range with its covariates, the bias of
// Eq. 8 with every bias term, its noise state, its modes' shifts, its most probable mode under the
// (extended) mixture and what is left once that mode is taken out.
#pragma once

#include <Eigen/Core>

#include "calibration/compensation.hpp"
#include "calibration/measured_data.hpp"
#include "core/calibration.hpp"
#include "core/covariate_table.hpp"
#include "core/extended_mixture.hpp"

namespace tofcomp::cli {

// The most probable "mode" of a range that the outlier component explains best.
inline constexpr int kOutlierMode = -1;

struct SearchResiduals {
  calibration::Compensation compensation;  // t̂^j, Hθ̂ + Σ bias terms, states, mode shifts
  core::CovariateTable covariates;
  core::ExtendedMixture mixture;  // the calibration's (core::compensation_mixture)
  Eigen::VectorXd residual;       // y − d − the bias (the modes still in it)
  // K × M: each range's posterior of each mode (Eq. 18 with the true distance; the outlier
  // component's share is what a row lacks of one).
  Eigen::MatrixXd responsibility;
  // The most probable mode of each range (0-based; kOutlierMode for the outlier component):
  // Eq. 18 with the true distance under the extended mixture (forward-backward under a chain).
  Eigen::VectorXi mode;
  // e_k = residual − μ_î − the shift of mode î, the mode-compensated residual; NaN for an outlier.
  Eigen::VectorXd e;
};

// Throws core::InvalidInput when the data lack a true distance.
SearchResiduals search_residuals(const calibration::MeasuredData& measured,
                                 const core::Calibration& calibration);

}  // namespace tofcomp::cli
