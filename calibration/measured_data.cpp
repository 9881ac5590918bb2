#include "calibration/measured_data.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

template <typename T>
std::vector<T> in_window(const std::vector<T>& events, double begin, double end) {
  std::vector<T> out;
  for (const auto& e : events) {
    if (e.first >= begin && e.first < end) out.push_back(e);
  }
  return out;
}

}  // namespace

bool MeasuredData::power_on_at(double time_s) const {
  bool on = true;
  for (const auto& [t, state] : power_changes) {
    if (t > time_s) break;
    on = state;
  }
  return on;
}

double MeasuredData::power_on_fraction(double begin_s, double end_s) const {
  if (!(end_s > begin_s)) return power_on_at(begin_s) ? 1.0 : 0.0;
  bool on = power_on_at(begin_s);
  double since = begin_s;
  double on_s = 0.0;
  for (const core::PowerChange& change : power_changes) {
    if (change.time_s <= begin_s) continue;
    if (change.time_s >= end_s) break;
    if (on) on_s += change.time_s - since;
    on = change.on;
    since = change.time_s;
  }
  if (on) on_s += end_s - since;
  return on_s / (end_s - begin_s);
}

double MeasuredData::last_power_on_at(double time_s) const {
  bool on = true;
  double since = powered_since_s;
  for (const auto& [t, state] : power_changes) {
    if (t > time_s) break;
    if (state && !on) since = t;
    on = state;
  }
  return since;
}

namespace {

// Every range a whole multiple of `step` mm, to within what a decimal file's parsing leaves
// (ranges below 100 m).
bool on_lattice(const Eigen::VectorXd& range_mm, double step) {
  constexpr double kLatticeTolerance = 1e-6;
  for (Eigen::Index k = 0; k < range_mm.size(); ++k) {
    const double cells = range_mm[k] / step;
    if (std::abs(cells - std::round(cells)) > kLatticeTolerance) return false;
  }
  return true;
}

constexpr Eigen::Index kMinRangesForUnits = 20;

}  // namespace

double MeasuredData::range_resolution_mm() const {
  return on_lattice(range_mm, kRangeResolutionMm) ? kRangeResolutionMm : 0.0;
}

void MeasuredData::require_millimetre_ranges() const {
  if (range_mm.size() < kMinRangesForUnits || !on_lattice(range_mm, kCentimetreRangeStepMm)) {
    return;
  }
  std::ostringstream msg;
  msg << source << ": all " << range_mm.size() << " ranges of beam " << beam
      << " are whole multiples of " << kCentimetreRangeStepMm
      << " mm, as the LMS 200 reports them in its cm units: lasing modes a few millimetres apart "
         "cannot be told apart at that step, and the calibration fits ranges to the millimetre. "
         "Record in mm units (tofcompd: link.units: mm; the LMS 200's units 0x01)";
  throw core::InvalidInput(msg.str());
}

Eigen::VectorXd MeasuredData::time_since_power_on() const {
  Eigen::VectorXd out(range_time_s.size());
  for (Eigen::Index k = 0; k < out.size(); ++k) {
    out[k] = range_time_s[k] - last_power_on_at(range_time_s[k]);
  }
  return out;
}

double MeasuredData::ambient_at(double time_s, double fallback_c) const {
  if (ambient.empty()) return fallback_c;
  // The last row at or before time_s (the log is in time order): O(log n).
  const auto after = std::upper_bound(
      ambient.begin(), ambient.end(), time_s,
      [](double t, const std::pair<double, double>& row) { return t < row.first; });
  return after == ambient.begin() ? ambient.front().second : std::prev(after)->second;
}

double MeasuredData::median_ambient_at_ranges(double fallback_c) const {
  if (ambient.empty() || range_time_s.size() == 0) return fallback_c;
  std::vector<double> at_ranges(static_cast<std::size_t>(range_time_s.size()));
  for (Eigen::Index k = 0; k < range_time_s.size(); ++k) {
    at_ranges[static_cast<std::size_t>(k)] = ambient_at(range_time_s[k], fallback_c);
  }
  const auto middle = at_ranges.begin() + static_cast<std::ptrdiff_t>(at_ranges.size() / 2);
  std::nth_element(at_ranges.begin(), middle, at_ranges.end());
  return *middle;
}

void MeasuredData::require_true_ranges() const {
  for (std::size_t k = 0; k < has_true_range.size(); ++k) {
    if (!has_true_range[k]) {
      std::ostringstream msg;
      msg << source << ": line " << (k < range_line.size() ? range_line[k] : 0)
          << ": range of beam " << beam
          << " has no true_range_mm in force; training and evaluation need the reference "
             "distance of every range (records of still surfaces without one train in the "
             "field from a bench calibration: tofcomp train BENCH.csv FIELD.csv --calibration "
             "BENCH.yaml, docs/field-calibration.md)";
      throw core::InvalidInput(msg.str());
    }
  }
  if (range_mm.size() == 0) {
    throw core::InvalidInput(source + ": no ranges for beam " + std::to_string(beam));
  }
}

MeasuredData MeasuredData::slice(double begin_s, double end_s) const {
  MeasuredData out;
  out.source = source;
  out.beam = beam;
  std::vector<Eigen::Index> ranges;
  for (Eigen::Index k = 0; k < range_time_s.size(); ++k) {
    if (range_time_s[k] >= begin_s && range_time_s[k] < end_s) ranges.push_back(k);
  }
  copy_ranges(ranges, out);
  std::vector<Eigen::Index> readings;
  for (Eigen::Index k = 0; k < temperature_time_s.size(); ++k) {
    if (temperature_time_s[k] >= begin_s && temperature_time_s[k] < end_s) readings.push_back(k);
  }
  out.temperature_time_s = temperature_time_s(readings);
  out.case_c = case_c(readings);
  // The power state in force at begin_s carries into the slice as a change at begin_s, and so
  // does when it was switched on.
  out.power_changes.push_back({begin_s, power_on_at(begin_s)});
  out.powered_since_s = last_power_on_at(begin_s);
  for (const core::PowerChange& e : power_changes) {
    if (e.time_s > begin_s && e.time_s < end_s) out.power_changes.push_back(e);
  }
  if (!ambient.empty()) {
    out.ambient.emplace_back(begin_s, ambient_at(begin_s, 0.0));
    for (const auto& e : in_window(ambient, begin_s, end_s)) {
      if (e.first > begin_s) out.ambient.push_back(e);
    }
  }
  return out;
}

void MeasuredData::copy_ranges(const std::vector<Eigen::Index>& ranges, MeasuredData& out) const {
  out.range_time_s = range_time_s(ranges);
  out.range_mm = range_mm(ranges);
  out.true_range_mm = true_range_mm(ranges);
  out.has_true_range.clear();
  out.range_line.clear();
  for (const auto k : ranges) {
    out.has_true_range.push_back(has_true_range[static_cast<std::size_t>(k)]);
    out.range_line.push_back(range_line.empty() ? 0 : range_line[static_cast<std::size_t>(k)]);
  }
}

MeasuredData MeasuredData::with_ranges(const std::vector<Eigen::Index>& ranges) const {
  MeasuredData out = *this;
  copy_ranges(ranges, out);
  return out;
}

core::CaseTemperatureLog case_log(const MeasuredData& data, double ambient_fallback_c) {
  const Eigen::Index k = data.temperature_time_s.size();
  if (k < 2) {
    throw core::InvalidInput(data.source + ": needs case_temp_c readings (found " +
                             std::to_string(k) + ")");
  }
  core::CaseTemperatureLog log;
  log.times_s = data.temperature_time_s;
  log.case_c = data.case_c;
  log.power_on_fraction.resize(k);
  log.ambient_c.resize(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    // Eq. 3's input is held over each interval (zero-order hold): the share of the interval to
    // the next reading the power was on, so that a switch between readings heats the model by
    // the energy it put in, not a whole interval early or late.
    log.power_on_fraction[i] =
        i + 1 < k ? data.power_on_fraction(log.times_s[i], log.times_s[i + 1])
                  : (data.power_on_at(log.times_s[i]) ? 1.0 : 0.0);
    log.ambient_c[i] = data.ambient_at(log.times_s[i], ambient_fallback_c);
  }
  return log;
}

double split_time(const MeasuredData& data, double fraction) {
  double first = std::numeric_limits<double>::infinity();
  double last = -std::numeric_limits<double>::infinity();
  auto extend = [&](const Eigen::VectorXd& t) {
    if (t.size() == 0) return;
    first = std::min(first, t[0]);
    last = std::max(last, t[t.size() - 1]);
  };
  extend(data.range_time_s);
  extend(data.temperature_time_s);
  if (!(last > first)) throw core::InvalidInput(data.source + ": the data span no time");
  const double target = first + fraction * (last - first);
  double best = target;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const auto& [t, on] : data.power_changes) {
    if (on && t > first && std::abs(t - target) < best_distance) {
      best = t;
      best_distance = std::abs(t - target);
    }
  }
  return best;
}

}  // namespace tofcomp::calibration
