// Thermal parameters shared by the thermal tests.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <random>

#include "core/thermal_identification.hpp"
#include "core/thermal_model.hpp"

namespace tofcomp::testing {

// Round numbers for hand computation, with fast time constants (≈ 6 s and 64 s) so that short
// records exercise the dynamics: R1 = 2, R2 = 4, C1 = 5, C2 = 10, P = 3.
inline core::ThermalParameters round_thermal_parameters() {
  return core::ThermalParameters{2.0, 4.0, 5.0, 10.0, 3.0};
}

// A 1 Hz log of the paper's experiment (§8.1): on/off cycles of uneven length in a 22 °C room
// (optionally a drifting one), case readings with Gaussian noise of noise_std_c, quantized to
// the LMS 200 sensor's 0.0625 °C when quantize is set. The device starts cold and off, so
// the predictor's initial state (at rest with the first reading) holds up to the reading's noise.
inline core::CaseTemperatureLog cycling_log(const core::ThermalParameters& truth,
                                            Eigen::Index seconds, unsigned seed, double noise_std_c,
                                            bool quantize, double ambient_swing_c = 0.0) {
  core::CaseTemperatureLog log;
  log.times_s = Eigen::VectorXd::LinSpaced(seconds, 0.0, static_cast<double>(seconds - 1));
  log.power_on_fraction.resize(seconds);
  log.ambient_c.resize(seconds);
  const int period[] = {1800, 1200, 2400, 900};
  Eigen::Index next_switch = 0;
  int cycle = 0;
  bool on = true;  // switched off at the first sample: the log starts with the device cold
  for (Eigen::Index i = 0; i < seconds; ++i) {
    if (i == next_switch) {
      on = !on;
      next_switch += period[cycle++ % 4];
    }
    log.power_on_fraction[i] = on ? 1.0 : 0.0;
    log.ambient_c[i] =
        22.0 + ambient_swing_c * std::sin(2.0 * std::numbers::pi * static_cast<double>(i) / 600.0);
  }
  log.case_c = core::simulate_at_times(truth, Eigen::Vector2d(22.0, 22.0), log.times_s,
                                       log.power_on_fraction, log.ambient_c)
                   .case_c;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_std_c);
  for (Eigen::Index i = 0; i < seconds; ++i) {
    log.case_c[i] += noise(rng);
    if (quantize) log.case_c[i] = 0.0625 * std::round(log.case_c[i] / 0.0625);
  }
  return log;
}

}  // namespace tofcomp::testing
