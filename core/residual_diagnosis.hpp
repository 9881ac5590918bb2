// Finds in the residuals of a trained Eq. 8 what the model lacks. After training, each range
// gets its most probable mode (Eq. 18) and its mode-compensated residual
// e_k = y_k − d − H_k θ̂ − μ_i, standardized z_k = e_k / σ_i. Each candidate effect is one
// established test against one covariate the data carry:
//   mode persistence            runs test on the sequence of most probable modes
//   temperature-dependent weights  χ² independence of mode and junction-temperature quartile
//   temperature-dependent spread  rank correlation of |z| with the junction temperature
//   outliers (heavy tails)      excess of |e − μ_nearest| > 8 robust σ (1.4826 × the MAD of
//                               the nearest-mode residuals, pooled: a broad mode the EM grew
//                               to hold the outliers cannot hide them) over the Gaussian tail
//   one more lasing mode        split likelihood-ratio test (universal inference) of M + 1
//                               modes against M on the residuals, each half fitted by EM
//   heating hysteresis          correlation of e with the junction's rate of change
//   time drift                  correlation of e with time
//   warm-up after power-on      correlation of e with exp(−t_on/τ), t_on the time since the
//                               power-on, the best τ of a grid (core/warm_up.hpp), Bonferroni
//                               over the grid
//   serial dependence           Ljung–Box on e (what is left once the above are accounted)
// A finding is significant at level α / (number of tests) (Bonferroni), so that data with no
// effect raise any finding with probability at most α. Significant findings come first, those
// of a structured effect before the generic symptoms (tails, serial dependence), each group by
// its z. Serial dependence is the one generic symptom: any unmodelled structure in time shows
// in it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/covariate_table.hpp"
#include "core/gaussian_mixture.hpp"
#include "core/statistical_tests.hpp"

namespace tofcomp::core {

enum class EffectKind {
  ModePersistence,
  TemperatureDependentWeights,
  TemperatureDependentSpread,
  Outliers,
  HeatingHysteresis,
  TimeDrift,
  WarmUp,
  ExtraMode,
  SerialDependence,
};

const char* effect_name(EffectKind kind);

struct Finding {
  EffectKind kind;
  std::string test;       // the test used, e.g. "runs test"
  std::string covariate;  // what the residual was tested against
  TestResult result;
  bool significant = false;
};

struct DiagnosisInput {
  Eigen::VectorXd time_s;
  Eigen::VectorXd junction_c;
  Eigen::VectorXd junction_rate_c_per_s;
  Eigen::VectorXd time_since_power_on_s;
  Eigen::VectorXd residual;  // y − d − H θ̂ (modes still in it)
};

struct DiagnosisOptions {
  double alpha = 0.05;  // family-wise false-alarm level
  int ljung_box_lags = 20;
  double tail_z = 8.0;
};

struct Diagnosis {
  std::vector<Finding> findings;  // ranked, most significant first
  Eigen::VectorXi mode;           // most probable mode of each range
  Eigen::VectorXd compensated;    // e_k
  Eigen::VectorXd standardized;   // z_k
};

// Throws InvalidInput on mismatched lengths, non-finite values or fewer than 100 ranges.
Diagnosis diagnose_residuals(const DiagnosisInput& input, const MixtureParameters& mixture,
                             const DiagnosisOptions& options = {});

}  // namespace tofcomp::core
