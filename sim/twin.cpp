#include "sim/twin.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::sim {
namespace {

std::discrete_distribution<int> make_mode_picker(const std::vector<LasingMode>& modes) {
  std::vector<double> weights;
  for (const auto& m : modes) weights.push_back(m.weight);
  return {weights.begin(), weights.end()};
}

double quantize(double value, double step) {
  return step * std::round(value / step);
}

// The power state at time t and the time of the next change after t (infinity at the end).
struct PowerAt {
  bool on;
  double next_change_s;
};

PowerAt power_at(const std::vector<PowerSegment>& schedule, double t) {
  double start = 0.0;
  for (const auto& segment : schedule) {
    const double end = start + segment.duration_s;
    if (t < end) return {segment.on, end};
    start = end;
  }
  return {schedule.empty() ? false : schedule.back().on, std::numeric_limits<double>::infinity()};
}

}  // namespace

Twin::Twin(Scenario scenario)
    : scenario_(std::move(scenario)),
      rng_(scenario_.seed),
      mode_picker_(make_mode_picker(scenario_.modes)),
      continuous_(core::continuous_model(scenario_.thermal)) {
  scenario_.validate();
  const double start_c =
      std::isnan(scenario_.initial_case_c) ? scenario_.ambient.at(0.0) : scenario_.initial_case_c;
  state_ = Eigen::Vector2d::Constant(start_c);
  was_on_ = power_on();
}

void Twin::note_power() {
  const bool on = power_on();
  if (on && !was_on_) powered_since_s_ = time_s_;
  was_on_ = on;
}

void Twin::set_power_override(std::optional<bool> on) {
  power_override_ = on;
  note_power();
}

double Twin::time_since_power_on_s() const {
  return was_on_ ? time_s_ - powered_since_s_ : 0.0;
}

bool Twin::power_on() const {
  return power_override_.value_or(power_at(scenario_.power, time_s_).on);
}

void Twin::advance_to(double time_s) {
  if (time_s < time_s_) {
    std::ostringstream msg;
    msg << "twin: cannot step back in time from " << time_s_ << " s to " << time_s << " s";
    throw core::InvalidInput(msg.str());
  }
  while (time_s_ < time_s) {
    const PowerAt power = power_override_
                              ? PowerAt{*power_override_, std::numeric_limits<double>::infinity()}
                              : power_at(scenario_.power, time_s_);
    const double end = std::min(time_s, power.next_change_s);
    const double step = end - time_s_;
    if (step > 0.0) {
      const core::DiscreteThermalModel model = core::discretize_zoh(scenario_.thermal, step);
      const double ambient = scenario_.ambient.at(0.5 * (time_s_ + end));
      state_ =
          model.a * state_ + model.b_power * (power.on ? 1.0 : 0.0) + model.b_ambient * ambient;
    }
    time_s_ = end;
    note_power();
  }
}

double Twin::read_case_sensor() {
  const auto& s = scenario_.sensor;
  const double noisy = case_c() + s.noise_std_c * standard_normal_(rng_);
  return s.resolution_c > 0.0 ? quantize(noisy, s.resolution_c) : noisy;
}

double Twin::junction_rate_c_per_s() const {
  const Eigen::Vector2d rate = continuous_.a * state_ +
                               continuous_.b_power * (power_on() ? 1.0 : 0.0) +
                               continuous_.b_ambient * ambient_c();
  return rate[1];
}

int Twin::draw_mode() {
  const TwinEffects& fx = scenario_.effects;
  if (fx.mode_persistence && last_mode_ >= 0 &&
      uniform_(rng_) < fx.mode_persistence->stay_probability) {
    return last_mode_;
  }
  if (!fx.temperature_dependent_weights) return mode_picker_(rng_);
  const double shift = fx.temperature_dependent_weights->log_odds_per_c *
                       (junction_c() - scenario_.bias.reference_c);
  std::vector<double> weights;
  for (std::size_t i = 0; i < scenario_.modes.size(); ++i) {
    weights.push_back(scenario_.modes[i].weight * (i == 0 ? 1.0 : std::exp(shift)));
  }
  std::discrete_distribution<int> picker(weights.begin(), weights.end());
  return picker(rng_);
}

RangeReading Twin::measure(int beam) {
  const TwinEffects& fx = scenario_.effects;
  RangeReading r;
  r.true_range_mm = scenario_.true_range_for_beam(beam);
  r.bias_mm = scenario_.bias.at(junction_c());
  if (fx.heating_hysteresis) {
    r.bias_mm += fx.heating_hysteresis->mm_per_c_per_min * 60.0 * junction_rate_c_per_s();
  }
  if (fx.time_drift) r.bias_mm += fx.time_drift->mm_per_hour * time_s_ / 3600.0;
  if (fx.warm_up) {
    r.bias_mm += fx.warm_up->amplitude_mm *
                 std::exp(-time_since_power_on_s() / fx.warm_up->time_constant_s);
  }
  r.mode = draw_mode();
  last_mode_ = r.mode;
  const LasingMode& mode = scenario_.modes[static_cast<std::size_t>(r.mode)];
  double spread = mode.std_mm;
  if (fx.temperature_dependent_spread) {
    const double x = junction_c() - scenario_.bias.reference_c;
    spread *= std::max(0.1, 1.0 + fx.temperature_dependent_spread->relative_per_c * x);
  }
  double analog = r.true_range_mm + r.bias_mm + mode.offset_mm + spread * standard_normal_(rng_);
  if (fx.outliers && uniform_(rng_) < fx.outliers->fraction) {
    analog = r.true_range_mm + fx.outliers->spread_mm * (2.0 * uniform_(rng_) - 1.0);
    r.mode = -1;
  }
  const double unit = scenario_.scanner.units == RangeUnits::Millimetre ? 1.0 : 10.0;
  r.range_mm = quantize(analog, unit);
  if (r.range_mm > scenario_.scanner.max_range_mm || r.range_mm < 0.0) {
    r.status = ReadingStatus::NoEcho;
  }
  return r;
}

void Twin::set_output(const ScannerOutput& output) {
  Scenario changed = scenario_;
  changed.scanner = output;
  changed.validate();
  scenario_.scanner = output;
}

std::vector<RangeReading> Twin::scan() {
  std::vector<RangeReading> readings;
  readings.reserve(static_cast<std::size_t>(scenario_.scanner.beams));
  for (int b = 0; b < scenario_.scanner.beams; ++b) readings.push_back(measure(b));
  return readings;
}

TwinSeries simulate_series(const Scenario& scenario, const std::function<void(double)>& progress) {
  Twin twin(scenario);
  TwinSeries out;
  const double end = scenario.duration_s();
  const double sensor_period = scenario.sensor.period_s;
  const double range_period =
      scenario.range_period_s > 0.0 ? scenario.range_period_s : 1.0 / scenario.scanner.scan_rate_hz;
  // Event times are computed from integer counts, so no rounding drift accumulates.
  long sensor_tick = 0;
  long range_tick = 0;
  bool last_power = !twin.power_on();
  double next_progress = 0.0;
  for (;;) {
    const double sensor_t = static_cast<double>(sensor_tick) * sensor_period;
    const double range_t = static_cast<double>(range_tick) * range_period;
    const double t = std::min(sensor_t, range_t);
    if (t >= end) break;
    twin.advance_to(t);
    const bool on = twin.power_on();
    if (on != last_power) {
      out.power_changes.push_back({t, on});
      last_power = on;
    }
    if (sensor_t <= range_t) {
      out.temperatures.push_back({t, twin.read_case_sensor(), twin.ambient_c()});
      ++sensor_tick;
    } else {
      if (on) {
        const auto readings = twin.scan();
        for (std::size_t b = 0; b < readings.size(); ++b) {
          const RangeReading& r = readings[b];
          if (r.status == ReadingStatus::Valid) {
            out.ranges.push_back({t, static_cast<int>(b), r.range_mm, r.true_range_mm,
                                  twin.junction_c(), r.bias_mm, r.mode});
          } else {
            ++out.no_echo_count;
          }
        }
      }
      ++range_tick;
    }
    if (progress && t >= next_progress) {
      progress(t / end);
      next_progress = t + end / 100.0;
    }
  }
  if (progress) progress(1.0);
  return out;
}

}  // namespace tofcomp::sim
