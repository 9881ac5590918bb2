// The digital twin of an LMS 200 on a bench: the thermal network of §3 driven by a power
// schedule and an ambient profile, a case sensor, and ranges drawn from Eq. 8 with a smooth
// temperature bias and hopping lasing modes, quantized as the device reports them.
//
// The twin steps in time, so the same object feeds the offline series (`tofcomp simulate`)
// and, in real time, the emulated devices. Seeded: one scenario and seed give one experiment.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include "core/power_change.hpp"
#include "sim/scenario.hpp"

namespace tofcomp::sim {

enum class ReadingStatus { Valid, NoEcho };

struct RangeReading {
  ReadingStatus status = ReadingStatus::Valid;
  double range_mm = 0.0;  // as reported: quantized to the output units
  double true_range_mm = 0.0;
  double bias_mm = 0.0;  // the temperature bias at this instant
  int mode = 0;          // the lasing mode that fired (0-based)
};

class Twin {
 public:
  explicit Twin(Scenario scenario);

  const Scenario& scenario() const { return scenario_; }
  double time_s() const { return time_s_; }
  bool power_on() const;
  double case_c() const { return state_[0]; }
  double junction_c() const { return state_[1]; }
  double ambient_c() const { return scenario_.ambient.at(time_s_); }

  // Integrates the thermal network exactly (zero-order hold) up to time_s, splitting the
  // interval at power changes. Throws InvalidInput when time_s is in the past.
  void advance_to(double time_s);
  // From now on the scanner's power is `on` whatever the schedule says (the laser's heat input
  // u of Eq. 4 is 0 while off), as when a host switches the supply; nullopt: the schedule again.
  void set_power_override(std::optional<bool> on);
  // Seconds since the scanner was last switched on (since t = 0 when it started on); 0 while off.
  double time_since_power_on_s() const;

  // A case-sensor reading now: the case temperature plus noise, quantized to the resolution.
  double read_case_sensor();
  // One range of one beam now (Eq. 8, the scenario's effects, the device's quantization and
  // range limit).
  RangeReading measure(int beam = 0);
  // A whole scan now: one reading per beam, in beam order.
  std::vector<RangeReading> scan();
  // dt^j/dt now, °C/s (Eq. 3).
  double junction_rate_c_per_s() const;
  // Changes what the device reports from now on (units, range limit, beams and field), as an
  // emulated device does when its host reconfigures it. Throws InvalidInput on a bad output.
  void set_output(const ScannerOutput& output);

 private:
  Scenario scenario_;
  std::mt19937_64 rng_;
  std::discrete_distribution<int> mode_picker_;
  std::normal_distribution<double> standard_normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  core::ContinuousThermalModel continuous_;
  double time_s_ = 0.0;
  std::optional<bool> power_override_;
  Eigen::Vector2d state_;
  int last_mode_ = -1;
  bool was_on_ = false;
  double powered_since_s_ = 0.0;

  int draw_mode();
  // Notes a power-on at the current time.
  void note_power();
};

// The single-beam series of one scenario, as a logger records it.
struct TwinSeries {
  struct Temperature {
    double time_s;
    double case_c;  // the sensor reading
    double ambient_c;
  };
  struct Range {
    double time_s;
    int beam;
    double range_mm;
    double true_range_mm;
    // Ground truth the data file does not carry, for tests.
    double junction_c;
    double bias_mm;
    int mode;
  };
  std::vector<Temperature> temperatures;
  std::vector<core::PowerChange> power_changes;
  std::vector<Range> ranges;
  int no_echo_count = 0;  // readings beyond the range limit, reported by the device as no echo
};

// Plays the whole power schedule: sensor readings every sensor period, a scan (one range per
// beam) every range_period_s while the power is on, and each power change. `progress` (may be
// empty) is called with the fraction done.
TwinSeries simulate_series(const Scenario& scenario,
                           const std::function<void(double)>& progress = {});

}  // namespace tofcomp::sim
