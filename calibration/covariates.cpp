#include "calibration/covariates.hpp"

namespace tofcomp::calibration {

core::CovariateTable covariate_table(const MeasuredData& data, const SmoothedJunction& junction) {
  core::CovariateSeries series;
  series.time_s = data.range_time_s;
  series.junction_c = junction.junction_c;
  series.time_since_power_on_s = data.time_since_power_on();
  if (!data.ambient.empty()) {
    series.ambient_c.resize(data.range_time_s.size());
    for (Eigen::Index k = 0; k < data.range_time_s.size(); ++k) {
      series.ambient_c[k] = data.ambient_at(data.range_time_s[k], data.ambient.front().second);
    }
  }
  series.heating_rate_c_per_min = junction.heating_rate_c_per_min;
  series.history_time_s = junction.history_time_s;
  series.history_junction_c = junction.history_junction_c;
  series.range_in_history = junction.range_in_history;
  return core::CovariateTable(std::move(series));
}

}  // namespace tofcomp::calibration
