#include "calibration/junction_estimate.hpp"

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::calibration {
namespace {

// The readings' prior at the first instant: ±0.5 °C on the case, ±2 °C on the junction.
constexpr double kPriorCaseStdC = 0.5;

}  // namespace

ThermalRecordGrid thermal_record_grid(const MeasuredData& data, double ambient_fallback_c) {
  if (data.temperature_time_s.size() == 0) {
    throw core::InvalidInput(data.source +
                             ": no case_temp_c readings: the junction temperature cannot be "
                             "estimated (§3.3)");
  }
  // Merge readings and ranges in time; a reading sorts before a range at the same instant.
  struct Instant {
    double time_s;
    bool reading;
    Eigen::Index index;
  };
  std::vector<Instant> instants;
  instants.reserve(
      static_cast<std::size_t>(data.temperature_time_s.size() + data.range_time_s.size()));
  for (Eigen::Index i = 0; i < data.temperature_time_s.size(); ++i) {
    instants.push_back({data.temperature_time_s[i], true, i});
  }
  for (Eigen::Index i = 0; i < data.range_time_s.size(); ++i) {
    instants.push_back({data.range_time_s[i], false, i});
  }
  std::stable_sort(instants.begin(), instants.end(), [](const Instant& a, const Instant& b) {
    return a.time_s < b.time_s || (a.time_s == b.time_s && a.reading && !b.reading);
  });

  const auto n = static_cast<Eigen::Index>(instants.size());
  ThermalRecordGrid grid;
  grid.time_s.resize(n);
  grid.power_on.resize(n);
  grid.ambient_c.resize(n);
  grid.reading_c.resize(n);
  grid.measured.resize(static_cast<std::size_t>(n));
  grid.range_in_grid.resize(data.range_time_s.size());
  grid.first_case_c = data.case_c[0];
  for (Eigen::Index g = 0; g < n; ++g) {
    const Instant& at = instants[static_cast<std::size_t>(g)];
    grid.time_s[g] = at.time_s;
    // Eq. 3's input held over each interval (zero-order hold): the share of the interval to the
    // next instant the power was on, so that a switch between instants heats the model by the
    // energy it put in (the case log's convention, calibration/measured_data.hpp).
    grid.power_on[g] =
        g + 1 < n ? data.power_on_fraction(at.time_s, instants[static_cast<std::size_t>(g) + 1].time_s)
                  : (data.power_on_at(at.time_s) ? 1.0 : 0.0);
    grid.ambient_c[g] = data.ambient_at(at.time_s, ambient_fallback_c);
    grid.reading_c[g] = at.reading ? data.case_c[at.index] : 0.0;
    grid.measured[static_cast<std::size_t>(g)] = at.reading;
    if (!at.reading) grid.range_in_grid[at.index] = static_cast<int>(g);
  }
  return grid;
}

SmoothedJunction junction_at_ranges(const ThermalRecordGrid& grid,
                                    const core::ThermalParameters& thermal,
                                    const core::ThermalNoise& noise) {
  const core::ThermalBelief prior = core::prior_at_case_temperature(
      thermal, grid.first_case_c, grid.ambient_c[0], kPriorCaseStdC);
  const core::SmoothedThermalRecord smoothed = core::smooth_thermal_record(
      thermal, noise, prior, grid.time_s, grid.power_on, grid.ambient_c, grid.reading_c,
      grid.measured);
  SmoothedJunction out;
  out.junction_c = smoothed.junction_mean_c(grid.range_in_grid);
  out.junction_std_c = smoothed.junction_std_c(grid.range_in_grid);
  // The model's rate at the smoothed state, not a slope of the smoothed junction over a window:
  // after a power-on the junction settles with R1 C1 (about 12 s on the datasheet), so a slope
  // over ±30 s flattened the rate where it is largest (and one-sided at the power-on itself).
  out.heating_rate_c_per_min.resize(grid.range_in_grid.size());
  for (Eigen::Index k = 0; k < grid.range_in_grid.size(); ++k) {
    const int g = grid.range_in_grid[k];
    out.heating_rate_c_per_min[k] =
        core::kSecondsPerMinute * core::junction_rate_c_per_s(thermal, smoothed.case_mean_c[g],
                                                              smoothed.junction_mean_c[g],
                                                              grid.power_on[g]);
  }
  out.range_in_history = grid.range_in_grid;
  out.history_time_s = grid.time_s;
  out.history_junction_c = smoothed.junction_mean_c;
  return out;
}

SmoothedJunction junction_at_ranges(const MeasuredData& data,
                                    const core::ThermalParameters& thermal,
                                    const core::ThermalNoise& noise, double ambient_fallback_c) {
  return junction_at_ranges(thermal_record_grid(data, ambient_fallback_c), thermal, noise);
}

const SmoothedJunction& RecordJunctions::at(const MeasuredData& beam) {
  const bool same_instants = computed_ && range_time_s_.size() == beam.range_time_s.size() &&
                             range_time_s_ == beam.range_time_s;
  if (!same_instants) {
    junction_ = junction_at_ranges(beam, thermal_, noise_, ambient_fallback_c_);
    range_time_s_ = beam.range_time_s;
    computed_ = true;
  }
  return junction_;
}

}  // namespace tofcomp::calibration
