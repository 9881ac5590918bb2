// §3.3, Eq. 7 in real time: the junction temperature t^j at each scan, from the case readings
// as they arrive, by the causal Kalman filter of core/kalman.hpp on the calibration's thermal
// model. Readings update the filter; a scan's junction temperature is the filter predicted to
// the scan's time (the filter itself is not moved, so a reading that arrives later is used at
// its own time). The scanner's power (the laser's heat input u of Eq. 4) is held between
// changes. Times are seconds on one monotonic clock.
//
// The junction's heating rate dt^j/dt, the covariate of the heating-hysteresis extension
// (core/model_extension.hpp), is Eq. 3's own at the predicted state: causal, instantaneous, the
// same function the offline search applies at the RTS-smoothed state (docs/daemon.md, "The
// heating rate"). The ambient t^a is the last ambient reading (a recording's ambient_c), the
// calibration's before the first.
#pragma once

#include <optional>

#include "core/calibration.hpp"
#include "core/kalman.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::realtime {

struct JunctionTrackerSettings {
  double stale_after_s = 10.0;          // a scan this long after the last reading is flagged
  double initial_case_std_c = 0.5;      // prior at the first reading
  bool operator==(const JunctionTrackerSettings&) const = default;
};

struct JunctionEstimate {
  bool valid = false;  // false until the first case reading
  double junction_c = 0.0;
  double junction_std_c = 0.0;
  double case_c = 0.0;  // the last reading accepted
  bool stale = false;   // no reading within stale_after_s of the scan
  // dt^j/dt in °C/min: Eq. 3's second line at the predicted state, power and ambient,
  // 60 · (u P / C1 + (t^c − t^j) / (R1 C1)) (the heating-hysteresis covariate).
  double heating_rate_c_per_min = 0.0;
  // Seconds since the scanner's power was last switched on (since the clock's origin when it
  // has been on throughout): the warm-up covariate.
  double time_since_power_on_s = 0.0;
  // The ambient t^a of Eq. 3 the filter ran at: the last ambient reading, or the calibration's
  // (the median its data logged) where none came; an ambient term's covariate.
  double ambient_c = 0.0;
};

class JunctionTracker {
 public:
  // Throws core::InvalidInput for settings that are not positive and finite.
  JunctionTracker(const core::Calibration& calibration, JunctionTrackerSettings settings = {});

  // A valid case reading t^s at time_s. A reading older than the filter's time is taken at the
  // filter's time (a step of zero). Throws core::InvalidInput on a non-finite value.
  void add_case_reading(double time_s, double case_c);
  // The scanner's power from time_s on (a switch-on restarts the time since power-on).
  void set_power(double time_s, bool on);
  // The ambient t^a of Eq. 3 from time_s on, held until the next reading (before the first:
  // the calibration's). Throws core::InvalidInput on a non-finite value.
  void set_ambient(double time_s, double ambient_c);
  // The last switch-on happened at time_s, before this tracker existed (a tracker restarted
  // on a new calibration keeps the scanner's warm-up clock).
  void set_last_switch_on(double time_s) { powered_since_s_ = time_s; }
  // t^j predicted to time_s (never before the last reading).
  JunctionEstimate at(double time_s) const;

 private:
  void advance_to(double time_s);
  double ambient_c() const { return ambient_c_.value_or(calibration_.ambient_c); }

  core::Calibration calibration_;
  JunctionTrackerSettings settings_;
  std::optional<core::ThermalKalmanFilter> filter_;
  double filter_time_s_ = 0.0;
  double last_reading_time_s_ = 0.0;
  double last_case_c_ = 0.0;
  bool power_on_ = true;
  double powered_since_s_ = 0.0;
  std::optional<double> ambient_c_;
};

}  // namespace tofcomp::realtime
