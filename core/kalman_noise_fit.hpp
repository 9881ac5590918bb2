// §3.3: the Kalman filter's noise levels (Eq. 7's W depends on them) chosen from the case log by
// the innovations' likelihood, where the paper leaves them to the designer.
//
// The filter of core/kalman.hpp run over a case log gives the log-likelihood of its readings,
// Σ_k log N(ν_k; 0, S_k) (the prediction-error decomposition). Its maximum over the three levels
// (q_c, q_j, r) is the maximum-likelihood choice. The search is coordinate-wise in log10 of each
// level (golden section on a bounded bracket, a few sweeps): three smooth one-dimensional
// problems, each cheap (one filter pass per evaluation).
//
// Not every level is seen by every log. A level whose starting value (the prior, e.g.
// core/kalman.hpp's LMS 200 levels) the log does not reject, by a likelihood-ratio test
// (the log-likelihood with that level back at its start loses less than
// NoiseFitOptions::determined_drop), is held there and reported as held, and the others are
// fitted again with it held: the data move a level only where they say the prior is wrong.
// Typically the junction's own process noise q_j is held: the case sees the junction only
// through R1 C2, so a case log hardly tells its level. Each level's profile a factor
// `profile_factor` up and down is reported beside.
#pragma once

#include <array>
#include <string>

#include "core/kalman.hpp"
#include "core/thermal_identification.hpp"

namespace tofcomp::core {

enum class KalmanNoiseLevel { kCaseProcess = 0, kJunctionProcess = 1, kSensor = 2 };
inline constexpr int kKalmanNoiseLevelCount = 3;
inline constexpr std::array<KalmanNoiseLevel, kKalmanNoiseLevelCount> kKalmanNoiseLevels = {
    KalmanNoiseLevel::kCaseProcess, KalmanNoiseLevel::kJunctionProcess, KalmanNoiseLevel::kSensor};
// "case process noise q_c", ... for people; "case_process", ... for files.
const char* kalman_noise_level_name(KalmanNoiseLevel level);
const char* kalman_noise_level_key(KalmanNoiseLevel level);

struct NoiseFitOptions {
  // Brackets of each level, as powers of ten (K²/s for q_c and q_j, K² for r).
  std::array<double, kKalmanNoiseLevelCount> min_log10 = {-12.0, -10.0, -7.0};
  std::array<double, kKalmanNoiseLevelCount> max_log10 = {-2.0, 0.0, 0.0};
  int sweeps = 3;                      // coordinate sweeps over the free levels
  double log10_tolerance = 0.01;       // golden-section bracket width at which a search stops
  double profile_factor = 10.0;        // how far up and down a level's profile is reported
  double determined_drop = 1.92;       // χ²(1) at 0.95, halved: a likelihood-ratio test's edge
  // The prior at the first reading (core::prior_at_case_temperature).
  double prior_case_std_c = 0.5;
};

struct KalmanNoiseLevelFit {
  double value = 0.0;
  bool held = false;           // the log does not reject the starting value: kept there
  double start_drop = 0.0;     // log-likelihood lost with this level back at its start
  double profile_drop_down = 0.0;  // log-likelihood lost at value / profile_factor
  double profile_drop_up = 0.0;    // and at value × profile_factor
};

struct KalmanNoiseFit {
  ThermalNoise noise;                      // the chosen levels
  ThermalNoise start;                      // where the search began (the held levels' values)
  std::array<KalmanNoiseLevelFit, kKalmanNoiseLevelCount> levels;
  double log_likelihood = 0.0;             // of the readings at `noise`
  double start_log_likelihood = 0.0;       // at `start`
  int evaluations = 0;                     // filter passes
};

// The readings' log-likelihood under the causal filter with these levels (one pass).
double innovations_log_likelihood(const CaseTemperatureLog& log,
                                  const ThermalParameters& parameters, const ThermalNoise& noise,
                                  const NoiseFitOptions& options = {});

// The levels by maximum likelihood from `start`, undetermined ones held at start. Throws
// InvalidInput for a log of fewer than three readings or an invalid start.
KalmanNoiseFit fit_kalman_noise(const CaseTemperatureLog& log, const ThermalParameters& parameters,
                                const ThermalNoise& start, const NoiseFitOptions& options = {});

}  // namespace tofcomp::core
