// Finds in the residuals of a trained Eq. 8 what the model lacks. After training, each range
// gets its most probable mode (Eq. 18) and its mode-compensated residual
// e_k = y_k − d − H_k θ̂ − μ_i, standardized z_k = e_k / σ_i. Each candidate effect is one
// established test against one covariate the data carry (core/residual_statistics.hpp):
//   mode persistence            runs test on the sequence of most probable modes
//   temperature-dependent weights  χ² independence of mode and junction-temperature quartile
//   temperature-dependent spread  rank correlation of |z| with the junction temperature
//   outliers (heavy tails)      excess of ranges beyond 8 robust σ of every lasing mode (and
//                               half the rounding) over what Gaussian modes put there
//   one more lasing mode        split likelihood-ratio test (universal inference) of M + 1
//                               modes against M on the residuals, each half fitted by EM
//   heating hysteresis          correlation of e with the junction's rate of change
//   time drift                  correlation of e with time
//   warm-up after power-on      correlation of e with exp(−t_on/τ), t_on the time since the
//                               power-on, the best τ of a grid (core/warm_up.hpp), Bonferroni
//                               over the grid
//   serial dependence           Ljung–Box on e (what is left once the above are accounted)
//
// What each statistic is judged against. The textbook laws (χ², normal) hold for independent,
// continuous residuals. The LMS 200 reports whole millimetres, and e is read off the most probable
// mode: where the rounding's lattice falls against the modes' boundaries decides how many ranges
// of a cell each mode takes and what their e is, and that position moves with d + H(t^j)θ̂, so
// with the junction temperature and everything that follows it (the time since power-on, the
// heating rate, the time). Under the paper's model itself, then, e correlates with those
// covariates and with its own past, and the modes' shares differ between temperature quartiles:
// on the foreign data sets (../shared/data/foreign), which hold Eq. 8 and nothing more, the
// textbook laws put the weights' χ² at p 1e-65 and the Ljung–Box at 1e-132. So the statistics are
// judged against draws of the trained model itself: each draw a mode by its weight and its
// Gaussian at every range (its variance less the rounding's h²/12, which a fit to rounded values
// holds: Sheppard's correction), the range rounded as the device rounds it, read by the same tests
// (the plug-in parametric bootstrap); a statistic's law is the normal (a correlation, the runs'
// z) or the scaled χ² (the weights' χ², Ljung–Box's Q) with the draws' mean and variance.
// The draws keep the trained parameters (they are not refitted), which makes the tests a little
// conservative where the fit has taken in part of a covariate's pattern. The outliers' count and
// the split likelihood ratio need no draws: the modes' tails bound the first (a range beyond the
// bound plus half the rounding was beyond the bound before it), the second is valid as it is.
//
// A finding is significant at level α / (number of tests) (Bonferroni), so that data with no
// effect raise any finding with probability at most α. Significant findings come first, those
// of a structured effect before the generic symptoms (tails, serial dependence), each group by
// its z. Serial dependence is the one generic symptom: any unmodelled structure in time shows
// in it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/gaussian_mixture.hpp"
#include "core/lms200_limits.hpp"
#include "core/parallel_for.hpp"
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
  // What the statistic was judged against: "64 draws of the trained model", "the modes'
  // Gaussian tails", "universal inference", or its textbook law.
  std::string reference;
  // The statistic's mean and standard deviation under the trained model: the draws' (for the
  // outliers' count, its expectation, the deviation NaN); NaN when the textbook law judged it.
  double null_mean = std::numeric_limits<double>::quiet_NaN();
  double null_std = std::numeric_limits<double>::quiet_NaN();
  // The p-value of the statistic's textbook law, which the draws correct (the same where no draws
  // judged it).
  double textbook_p_value = 1.0;
};

struct DiagnosisInput {
  Eigen::VectorXd time_s;
  Eigen::VectorXd junction_c;
  Eigen::VectorXd junction_rate_c_per_s;
  Eigen::VectorXd time_since_power_on_s;
  Eigen::VectorXd residual;  // y − d − H θ̂ (modes still in it)
  // d + H θ̂ at each range, the range less its residual: where a draw of the trained model is
  // rounded as the device rounded the range. Needed when DiagnosisOptions::resolution_mm > 0.
  Eigen::VectorXd predicted_mm;
};

// The draws of the trained model that judge the tests: 64 put a statistic's standard deviation
// within about 9 % (1/√(2·63)) and cost a few tenths of a second on a day of ranges; their seeds
// follow from one fixed seed, so a diagnosis is the same on every run and any number of threads.
inline constexpr int kResidualNullDraws = 64;
inline constexpr std::uint64_t kResidualNullSeed = 20151211;

struct DiagnosisOptions {
  double alpha = 0.05;  // family-wise false-alarm level
  int ljung_box_lags = 20;
  double tail_z = 8.0;
  // The widest a lasing mode spreads: the LMS 200's statistical error of a range (1σ). The outliers
  // are measured against the modes no wider than this.
  double max_lasing_spread_mm = lms200::kStatisticalErrorMm;
  // The ranges' rounding (mm; the LMS 200: 1), which the draws repeat; 0: unrounded ranges.
  double resolution_mm = 0.0;
  // Draws of the trained model that judge the statistics; 0: their textbook laws.
  int null_draws = kResidualNullDraws;
  std::uint64_t seed = kResidualNullSeed;
  // Draws at once (none: one after the other); the result does not depend on it.
  ParallelFor parallel;
};

struct Diagnosis {
  std::vector<Finding> findings;  // ranked, most significant first
  Eigen::VectorXi mode;           // most probable mode of each range
  Eigen::VectorXd compensated;    // e_k
  Eigen::VectorXd standardized;   // z_k
  // The outliers' test: each mode's robust scale (mm) and the lasing modes the residuals were
  // measured against (0-based).
  Eigen::VectorXd mode_scale_mm;
  std::vector<int> lasing_modes;
  double resolution_mm = 0.0;  // the rounding the draws repeated and the outliers' bound allows
};

// Throws InvalidInput on mismatched lengths, non-finite values, fewer than 100 ranges, or a
// resolution with no predicted ranges.
Diagnosis diagnose_residuals(const DiagnosisInput& input, const MixtureParameters& mixture,
                             const DiagnosisOptions& options = {});

}  // namespace tofcomp::core
