#include "calibration/junction_estimate.hpp"

#include <algorithm>
#include <vector>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

// The readings' prior at the first instant: ±0.5 °C on the case, ±2 °C on the junction.
constexpr double kPriorCaseStdC = 0.5;

}  // namespace

SmoothedJunction junction_at_ranges(const MeasuredData& data,
                                    const core::ThermalParameters& thermal,
                                    const core::ThermalNoise& noise, double ambient_fallback_c) {
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
  std::vector<Instant> grid;
  grid.reserve(static_cast<std::size_t>(data.temperature_time_s.size() + data.range_time_s.size()));
  for (Eigen::Index i = 0; i < data.temperature_time_s.size(); ++i) {
    grid.push_back({data.temperature_time_s[i], true, i});
  }
  for (Eigen::Index i = 0; i < data.range_time_s.size(); ++i) {
    grid.push_back({data.range_time_s[i], false, i});
  }
  std::stable_sort(grid.begin(), grid.end(), [](const Instant& a, const Instant& b) {
    return a.time_s < b.time_s || (a.time_s == b.time_s && a.reading && !b.reading);
  });

  const auto n = static_cast<Eigen::Index>(grid.size());
  Eigen::VectorXd times(n), power(n), ambient(n), reading(n);
  std::vector<bool> measured(static_cast<std::size_t>(n));
  for (Eigen::Index g = 0; g < n; ++g) {
    const Instant& at = grid[static_cast<std::size_t>(g)];
    times[g] = at.time_s;
    // Eq. 3's input held over each interval (zero-order hold): the share of the interval to the
    // next instant the power was on, so that a switch between instants heats the model by the
    // energy it put in (the case log's convention, calibration/measured_data.hpp).
    power[g] = g + 1 < n ? data.power_on_fraction(at.time_s, grid[static_cast<std::size_t>(g) + 1].time_s)
                         : (data.power_on_at(at.time_s) ? 1.0 : 0.0);
    ambient[g] = data.ambient_at(at.time_s, ambient_fallback_c);
    reading[g] = at.reading ? data.case_c[at.index] : 0.0;
    measured[static_cast<std::size_t>(g)] = at.reading;
  }
  const core::ThermalBelief prior = core::prior_at_case_temperature(
      thermal, data.case_c[0], ambient[0], kPriorCaseStdC);
  const core::SmoothedThermalRecord smoothed =
      core::smooth_thermal_record(thermal, noise, prior, times, power, ambient, reading, measured);

  SmoothedJunction out;
  out.junction_c.resize(data.range_time_s.size());
  out.junction_std_c.resize(data.range_time_s.size());
  out.range_in_history.resize(data.range_time_s.size());
  out.history_time_s = times;
  out.history_junction_c = smoothed.junction_mean_c;
  for (Eigen::Index g = 0; g < n; ++g) {
    const Instant& at = grid[static_cast<std::size_t>(g)];
    if (at.reading) continue;
    out.junction_c[at.index] = smoothed.junction_mean_c[g];
    out.junction_std_c[at.index] = smoothed.junction_std_c[g];
    out.range_in_history[at.index] = static_cast<int>(g);
  }
  return out;
}

}  // namespace tofcomp::calibration
