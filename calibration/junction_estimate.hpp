// §3.3: the junction temperature t^j at every range of measured data, by the Kalman filter and
// RTS smoother of Eq. 7 over the case readings (core/kalman.hpp). Offline, so the smoother uses
// the readings after each range too; the daemon's causal filter is realtime/junction_tracker.hpp.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "calibration/measured_data.hpp"
#include "core/kalman.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::calibration {

// Junction temperature at every range instant by the RTS smoother (§3.3, Eq. 7) over the
// merged time grid of readings and ranges.
// Also the smoothed junction over the whole merged grid (power-off gaps included), with each
// range's place in it: the history the junction's lag runs over (core/covariate_table.hpp).
// And the junction's heating rate at every range: Eq. 3's second line at the smoothed state and
// the power (core::junction_rate_c_per_s), the rate the daemon computes at its filter's state.
struct SmoothedJunction {
  Eigen::VectorXd junction_c;
  Eigen::VectorXd junction_std_c;
  Eigen::VectorXd heating_rate_c_per_min;
  Eigen::VectorXd history_time_s;
  Eigen::VectorXd history_junction_c;
  Eigen::VectorXi range_in_history;
};
SmoothedJunction junction_at_ranges(const MeasuredData& data,
                                    const core::ThermalParameters& thermal,
                                    const core::ThermalNoise& noise, double ambient_fallback_c);

// What the smoother runs over, which does not depend on the thermal parameters: the merged time
// grid of readings and ranges with Eq. 3's inputs on it. Built once for a search that smooths
// the same data at many parameters (calibration/junction_dynamics.hpp).
struct ThermalRecordGrid {
  Eigen::VectorXd time_s;
  Eigen::VectorXd power_on;   // the share of each interval to the next instant the power was on
  Eigen::VectorXd ambient_c;
  Eigen::VectorXd reading_c;  // the case reading at a reading's instant, 0 elsewhere
  std::vector<bool> measured;
  Eigen::VectorXi range_in_grid;  // each range's instant
  double first_case_c = 0.0;
};
// Throws InvalidInput when the data carry no case readings.
ThermalRecordGrid thermal_record_grid(const MeasuredData& data, double ambient_fallback_c);
SmoothedJunction junction_at_ranges(const ThermalRecordGrid& grid,
                                    const core::ThermalParameters& thermal,
                                    const core::ThermalNoise& noise);

// The smoothed junction of the beams of one record, one beam after another: the beams of a scan
// share its instant, so beams with the same range times share the smoothing, done once for them
// (the smoother runs over the whole case log: many beams of a day took it as many times).
class RecordJunctions {
 public:
  RecordJunctions(const core::ThermalParameters& thermal, const core::ThermalNoise& noise,
                  double ambient_fallback_c)
      : thermal_(thermal), noise_(noise), ambient_fallback_c_(ambient_fallback_c) {}
  // The junction at the ranges of `beam`, a beam of the record the earlier calls took.
  const SmoothedJunction& at(const MeasuredData& beam);

 private:
  core::ThermalParameters thermal_;
  core::ThermalNoise noise_;
  double ambient_fallback_c_;
  Eigen::VectorXd range_time_s_;  // the times the junction below is at
  SmoothedJunction junction_;
  bool computed_ = false;
};

}  // namespace tofcomp::calibration
