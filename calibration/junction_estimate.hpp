// §3.3: the junction temperature t^j at every range of measured data, by the Kalman filter and
// RTS smoother of Eq. 7 over the case readings (core/kalman.hpp). Offline, so the smoother uses
// the readings after each range too; the daemon's causal filter is realtime/junction_tracker.hpp.
#pragma once

#include <Eigen/Core>

#include "calibration/measured_data.hpp"
#include "core/kalman.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::calibration {

// Junction temperature at every range instant by the RTS smoother (§3.3, Eq. 7) over the
// merged time grid of readings and ranges.
struct SmoothedJunction {
  Eigen::VectorXd junction_c;
  Eigen::VectorXd junction_std_c;
};
SmoothedJunction junction_at_ranges(const MeasuredData& data,
                                    const core::ThermalParameters& thermal,
                                    const core::ThermalNoise& noise, double ambient_fallback_c);

}  // namespace tofcomp::calibration
