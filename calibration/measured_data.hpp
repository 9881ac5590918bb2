// Measured data as the analyses need it: one beam's ranges with their reference distance, the
// case-temperature log, the power changes and the ambient log, as plain vectors. Filled from the
// interchange CSV (calibration/measured_data_reader.hpp) or from the twin.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/power_change.hpp"
#include "core/thermal_identification.hpp"

namespace tofcomp::calibration {

// The LMS 200 reports whole millimetres: the rounding the Cramér–Rao bound accounts for, and
// the reason no lasing mode is narrower than the rounding's own spread (training's variance
// floor, calibration/training.hpp).
inline constexpr double kRangeResolutionMm = 1.0;
// Ranges rounded to whole millimetres carry the rounding's variance h²/12 (Sheppard) in every
// mode: a mode narrower than that is the rounding's lattice, not a lasing mode, and left free EM
// would lock a mode onto one rounded value (the likelihood of rounded data is unbounded).
inline double rounding_variance_mm2() { return kRangeResolutionMm * kRangeResolutionMm / 12.0; }
// The LMS 200's other range unit (its cm units: the 8 m mode then reaches 80 m).
inline constexpr double kCentimetreRangeStepMm = 10.0;

struct MeasuredData {
  std::string source;  // file name, for messages and provenance
  int beam = 0;
  // Ranges of the beam, in time order.
  Eigen::VectorXd range_time_s;
  Eigen::VectorXd range_mm;
  Eigen::VectorXd true_range_mm;  // valid where has_true_range
  std::vector<bool> has_true_range;
  std::vector<long> range_line;  // the CSV line of each range, for messages (0: none)
  // Case-temperature readings t^s.
  Eigen::VectorXd temperature_time_s;
  Eigen::VectorXd case_c;
  // Power changes (time, on), in time order; the power is on before the first.
  std::vector<core::PowerChange> power_changes;
  // When the power, on before the first change, was switched on: the start of the experiment
  // (time 0), or in a slice the last power-on before it.
  double powered_since_s = 0.0;
  // Logged ambient (time, °C); empty when the data carry none.
  std::vector<std::pair<double, double>> ambient;

  bool power_on_at(double time_s) const;
  // The share of [begin_s, end_s) the power was on (power_on_at(begin_s) for an empty interval).
  double power_on_fraction(double begin_s, double end_s) const;
  // The time of the last switch-on at or before time_s (powered_since_s when none).
  double last_power_on_at(double time_s) const;
  // Seconds since the last switch-on at each range (the warm-up covariate).
  Eigen::VectorXd time_since_power_on() const;
  // kRangeResolutionMm when every range is a whole multiple of it, as the LMS 200 reports them;
  // 0 when some are not (ranges a logger averaged or scaled), so that no rounding is assumed.
  double range_resolution_mm() const;
  // Throws core::InvalidInput when every range is a whole multiple of kCentimetreRangeStepMm, as
  // the LMS 200 reports them in its cm units: lasing modes a few millimetres apart are not told
  // apart at that step, and training fits ranges rounded to kRangeResolutionMm (on ranges 10 mm
  // apart a mode of σ 0.29 mm took 91 % of them). Records of fewer than 20 ranges are not judged
  // (by chance every one of 20 ranges in mm lies on a whole cm with probability 1e-20).
  void require_millimetre_ranges() const;
  // The last logged ambient at or before time_s (the first one before it), or fallback.
  double ambient_at(double time_s, double fallback_c) const;
  // The median of ambient_at over the ranges' instants: the ambient the ranges were measured
  // in, which a calibration carries for a daemon that has no ambient sensor; fallback when the
  // data log no ambient or have no ranges.
  double median_ambient_at_ranges(double fallback_c) const;
  // Throws core::InvalidInput unless every range has a true distance, naming the first line
  // that has none.
  void require_true_ranges() const;
  // The subset of ranges, temperatures, power and ambient in [begin_s, end_s).
  MeasuredData slice(double begin_s, double end_s) const;
  // The same record with only these ranges (indices, in time order); the case log, the power
  // and the ambient whole.
  MeasuredData with_ranges(const std::vector<Eigen::Index>& ranges) const;

 private:
  // `ranges` of this record's into out's range vectors.
  void copy_ranges(const std::vector<Eigen::Index>& ranges, MeasuredData& out) const;
};

// The case log of the thermal identification (§3.2) at the temperature readings.
core::CaseTemperatureLog case_log(const MeasuredData& data, double ambient_fallback_c);

// The time that splits the data into a training part and a test part (§8): the power-on
// closest to the given fraction of the duration, so each part holds whole heating cycles; the
// fraction of the time itself when there is no power-on.
double split_time(const MeasuredData& data, double fraction);

}  // namespace tofcomp::calibration
