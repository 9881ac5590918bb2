#include "sim/scenario.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::sim {
namespace {

void require(bool ok, const std::string& field, const std::string& why) {
  if (!ok) throw core::InvalidInput("scenario: " + field + " " + why);
}

}  // namespace

double AmbientProfile::at(double time_s) const {
  double value = base_c + drift_c_per_hour * time_s / 3600.0;
  for (const auto& step : steps) {
    if (time_s >= step.time_s) value += step.change_c;
  }
  return value;
}

double RangeBias::at(double junction_c) const {
  const double x = junction_c - reference_c;
  const double knee = knee_width_c > 0.0 ? knee_amplitude_mm * std::tanh(x / knee_width_c) : 0.0;
  return slope_mm_per_c * x + curvature_mm_per_c2 * x * x + knee;
}

double ScannerOutput::beam_angle_deg(int beam) const {
  if (beams <= 1) return 0.0;
  return -0.5 * field_deg + field_deg * beam / (beams - 1);
}

double Scenario::true_range_for_beam(int beam) const {
  const double cosine = std::cos(scanner.beam_angle_deg(beam) * std::numbers::pi / 180.0);
  return cosine > 1e-6 ? true_range_mm / cosine : std::numeric_limits<double>::infinity();
}

double Scenario::duration_s() const {
  double total = 0.0;
  for (const auto& segment : power) total += segment.duration_s;
  return total;
}

void Scenario::validate() const {
  thermal.validate();
  require(!power.empty(), "power", "needs at least one segment");
  for (std::size_t i = 0; i < power.size(); ++i) {
    require(power[i].duration_s > 0.0 && std::isfinite(power[i].duration_s),
            "power[" + std::to_string(i) + "].duration_s", "must be a positive number of seconds");
  }
  require(std::isfinite(ambient.base_c), "ambient.base_c", "must be finite");
  require(sensor.period_s > 0.0, "sensor.period_s", "must be positive");
  require(sensor.noise_std_c >= 0.0, "sensor.noise_std_c", "must be non-negative");
  require(sensor.resolution_c >= 0.0, "sensor.resolution_c", "must be non-negative");
  require(true_range_mm > 0.0, "true_range_mm", "must be positive");
  require(!modes.empty(), "modes", "needs at least one lasing mode");
  double weight_sum = 0.0;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::string field = "modes[" + std::to_string(i) + "]";
    require(modes[i].std_mm > 0.0, field + ".std_mm", "must be positive");
    require(modes[i].weight > 0.0, field + ".weight", "must be positive");
    weight_sum += modes[i].weight;
  }
  require(std::abs(weight_sum - 1.0) < 1e-9, "modes[*].weight", "must sum to 1");
  require(scanner.max_range_mm > 0.0, "scanner.max_range_mm", "must be positive");
  require(scanner.beams >= 1, "scanner.beams", "must be at least 1");
  require(scanner.scan_rate_hz > 0.0, "scanner.scan_rate_hz", "must be positive");
  require(scanner.field_deg > 0.0 && scanner.field_deg <= 180.0, "scanner.field_deg",
          "must be in (0, 180]");
  if (effects.mode_persistence) {
    const double p = effects.mode_persistence->stay_probability;
    require(p >= 0.0 && p < 1.0, "effects.mode_persistence.stay_probability", "must be in [0, 1)");
  }
  if (effects.outliers) {
    require(effects.outliers->fraction >= 0.0 && effects.outliers->fraction <= 0.5,
            "effects.outliers.fraction", "must be in [0, 0.5]");
    require(effects.outliers->spread_mm > 0.0, "effects.outliers.spread_mm", "must be positive");
  }
  if (effects.warm_up) {
    require(std::isfinite(effects.warm_up->amplitude_mm), "effects.warm_up.amplitude_mm",
            "must be finite");
    require(effects.warm_up->time_constant_s > 0.0, "effects.warm_up.time_constant_s",
            "must be positive");
  }
  require(range_period_s >= 0.0, "range_period_s", "must be non-negative");
}

}  // namespace tofcomp::sim
