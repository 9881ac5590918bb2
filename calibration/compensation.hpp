// A calibration applied to measured data offline: the bias H(t^j)θ̂ of Eq. 8 at each range from
// the smoothed junction temperature, the mixture the ranges are compensated under, and the
// held-out likelihood of the ranges.
#pragma once

#include "calibration/junction_estimate.hpp"
#include "calibration/measured_data.hpp"
#include "core/calibration.hpp"
#include "core/extended_mixture.hpp"

namespace tofcomp::calibration {

// The bias H θ̂ at each range of `data` under a calibration, from the smoothed junction
// temperature. With an extension (core/model_extension.hpp) the bias also carries its bias
// terms, and each range has its noise state and its modes' offset shifts (K × M; empty without
// mode-offset terms).
struct Compensation {
  SmoothedJunction junction;
  Eigen::VectorXd bias_mm;
  Eigen::VectorXi noise_state;
  Eigen::MatrixXd mode_shift;
};
Compensation compensate(const MeasuredData& data, const core::Calibration& calibration);
// The same on a junction already smoothed under the calibration's thermal model and noise.
Compensation compensate(const MeasuredData& data, const core::Calibration& calibration,
                        SmoothedJunction junction);

// log p(y − d | calibration) over the ranges of data with a known distance: the held-out
// criterion of an extension.
double held_out_log_likelihood(const MeasuredData& data, const core::Calibration& calibration,
                               const Compensation& compensation);

}  // namespace tofcomp::calibration
