// A scenario of the digital twin: everything that makes one simulated experiment, as plain
// values. Loaded from YAML by sim/scenario_yaml.hpp; documented in docs/scenarios.md.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/thermal_model.hpp"
#include "sim/effects.hpp"

namespace tofcomp::sim {

// One stretch of the power schedule: the scanner on (laser heating) or off for a duration.
struct PowerSegment {
  bool on = true;
  double duration_s = 0.0;
};

// Ambient temperature: base, plus steps at given times, plus a linear drift.
struct AmbientStep {
  double time_s = 0.0;
  double change_c = 0.0;
};
struct AmbientProfile {
  double base_c = 22.0;
  std::vector<AmbientStep> steps;
  double drift_c_per_hour = 0.0;

  double at(double time_s) const;
};

// The temperature sensor on the scanner's case (the paper's t^s).
struct CaseSensor {
  double period_s = 1.0;         // one reading per period
  double noise_std_c = 0.02;     // white noise before quantization
  double resolution_c = 0.0625;  // a DS18B20 / TMP102 step
};

// The range bias left by the device's own temperature compensation (the shape of Fig. 4), a
// smooth function of the junction temperature t:
//   slope (t − ref) + curvature (t − ref)² + knee_amplitude tanh((t − ref) / knee_width).
struct RangeBias {
  double reference_c = 26.8;
  double slope_mm_per_c = -1.2;
  double curvature_mm_per_c2 = 0.15;
  double knee_amplitude_mm = -1.0;
  double knee_width_c = 0.8;

  double at(double junction_c) const;
};

// One lasing mode: an offset, a spread and a weight (Fig. 3).
struct LasingMode {
  double offset_mm = 0.0;
  double std_mm = 1.0;
  double weight = 0.5;
};

enum class RangeUnits { Millimetre, Centimetre };

// What the LMS 200 reports: units, the largest range it measures in that mode, and how
// many beams a scan has.
struct ScannerOutput {
  RangeUnits units = RangeUnits::Millimetre;
  double max_range_mm = 8183.0;  // 8 m mode: codes above are reserved
  int beams = 1;                 // 1 for a single-beam series; 181, 361 or 401 for scans
  double field_deg = 180.0;      // the scan's angular field (100 or 180)
  double scan_rate_hz = 75.0;    // the mirror's rate

  // The angle of a beam from the scan's centre line, in degrees.
  double beam_angle_deg(int beam) const;
};

struct Scenario {
  std::string name = "default";
  std::uint64_t seed = 1;
  core::ThermalParameters thermal{};
  std::vector<PowerSegment> power;  // played in order from t = 0
  AmbientProfile ambient;
  // The case temperature at t = 0, the junction in equilibrium with it (power off); NaN: the
  // scanner starts cold, at ambient.
  double initial_case_c = std::numeric_limits<double>::quiet_NaN();
  CaseSensor sensor;
  // The target: a flat wall at this distance, square to the scan's centre line; beam b sees it
  // at true_range_mm / cos(angle_b). A single beam looks straight at it.
  double true_range_mm = 3000.0;
  RangeBias bias;
  std::vector<LasingMode> modes;
  ScannerOutput scanner;
  // Single-beam series: one range every range_period_s while the power is on (the paper's
  // 20,000 samples). Zero: every scan.
  double range_period_s = 1.0;
  TwinEffects effects;  // none by default

  // The distance beam b measures to the wall (may exceed the range limit).
  double true_range_for_beam(int beam) const;

  // Total length of the power schedule.
  double duration_s() const;
  // Throws core::InvalidInput naming the field when a value is out of range.
  void validate() const;
};

}  // namespace tofcomp::sim
