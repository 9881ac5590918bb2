// The covariates of the grammar (core/effect_grammar.hpp) at each range of measured data: the
// smoothed junction temperature and its history (§3.3), the time, the time since power-on and
// the logged ambient.
#pragma once

#include "calibration/junction_estimate.hpp"
#include "calibration/measured_data.hpp"
#include "core/covariate_table.hpp"

namespace tofcomp::calibration {

core::CovariateTable covariate_table(const MeasuredData& data, const SmoothedJunction& junction);

}  // namespace tofcomp::calibration
