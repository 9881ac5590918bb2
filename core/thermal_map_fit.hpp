// §3.2 with the datasheet as a prior: a maximum a posteriori fit of the thermal network (Eq. 3)
// to a case-temperature log that never refuses usable data.
//
// The prediction-error method of core/thermal_identification.hpp fits only the parameters it is
// told to free and refuses a log that does not determine them all. A log from a scanner we did
// not make determines some combinations of (R1, R2, C1, C2, P) well (the gain P R2 and the slow
// time constant, from every power switch), others faintly (the fast time constant R1 C1, through
// the delay it adds to a switch), and one never (the heat scale, header of
// thermal_identification.hpp). Which ones depends on the log, not on a fixed list. So every
// parameter is free here, each with a log-normal prior centred on Algorithm 1's value:
//
//   minimize  (K_eff / 2) log Σ_k (ŷ_k(θ) − y_k)²  +  ½ Σ_i ((θ_i − θ0_i) / s_i)²,   θ = log p,
//
// the negative log posterior with the noise variance profiled out (σ̂² = SSR / K_eff) and
// s_i = prior_log_std. K_eff is the number of independent residuals: the output error of a slow
// thermal system is strongly correlated from one reading to the next, and counting every reading
// as independent would let the data overrule the prior along directions they barely see. It is
// K (1 − ρ) / (1 + ρ), ρ the lag-1 autocorrelation of the residuals (the AR(1) variance
// inflation), measured at the optimum of a first fit with K_eff = K and then held for the final
// fit. Levenberg–Marquardt on θ with the exact Jacobian (case_temperature_sensitivity).
//
// What the data determine is read off their information, not from a list: the information
// matrix of the data whitened by the prior, S^½ JᵀJ S^½ / σ̂², has an eigenvalue per direction
// of θ. The fit moves θ only along directions whose eigenvalue reaches min_data_over_prior (the
// data know them ten times more precisely than the datasheet); the others are held at the
// datasheet and reported, with their eigenvalues. The directions are found at the datasheet for
// the first fit and at its answer for the final one, which starts again from the datasheet.
// Per parameter, the data share 1 − var_post / var_prior says how much of its prior uncertainty
// the log removed; a parameter with a share below held_below_data_share is reported as held at
// the datasheet value. Each estimate carries its posterior standard deviation of log p (≈ its
// relative standard error).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/thermal_identification.hpp"

namespace tofcomp::core {

struct MapFitOptions {
  // One prior standard deviation of log p for every parameter: ln 2 says that a datasheet value
  // of another unit of the family is right within a factor of 2 at one σ (of 4 at two).
  double prior_log_std = 0.6931471805599453;
  int max_iterations = 200;
  double step_tolerance = 1e-9;
  double relative_cost_tolerance = 1e-12;
  double max_log_step = 1.0;
  // A direction of θ is fitted only where the data determine it: their information along it, over
  // the prior's, at least this (the data know it ten times more precisely than the datasheet);
  // every other direction is held at the datasheet. Model error the fit cannot tell from signal
  // (a sensor's lag, an ambient logged coarsely) then cannot drag the faint directions.
  double min_data_over_prior = 100.0;
  // A parameter whose data share is below this is reported as held at the datasheet value.
  double held_below_data_share = 0.5;
  // Throws InvalidInput naming the first bad option.
  void validate() const;
};

// A direction of log-parameter space held at the datasheet (unit length, in ThermalParameter
// order), with the data's information along it over the prior's (below min_data_over_prior).
struct PriorHeldDirection {
  std::array<double, kThermalParameterCount> log_direction{};
  double data_over_prior = 0.0;
};

struct MapFitResult : ThermalFitResult {
  ThermalParameters prior;  // Algorithm 1's answer, the prior's centre
  // Posterior standard deviation of log p, and the data share 1 − var_post / var_prior, per
  // parameter in ThermalParameter order; held: the share is below held_below_data_share.
  std::array<double, kThermalParameterCount> relative_std{};
  std::array<double, kThermalParameterCount> data_share{};
  std::array<bool, kThermalParameterCount> held{};
  std::vector<PriorHeldDirection> prior_held_directions;  // weakest first
  double residual_lag1_correlation = 0.0;                 // ρ
  double effective_samples = 0.0;                         // K_eff
};

// The MAP fit of all five parameters around `datasheet` (Algorithm 1's answer). Needs at least
// two readings. Throws InvalidInput on a bad log or options; never refuses a log for what it does
// not determine (that is reported as held).
MapFitResult identify_with_datasheet_prior(const CaseTemperatureLog& log,
                                           const ThermalParameters& datasheet,
                                           const MapFitOptions& options = {});

}  // namespace tofcomp::core
