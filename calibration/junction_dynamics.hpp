// §3.2-§3.3 completed by the ranges: the junction's own dynamics, which a case log barely sees.
//
// A case log determines the case's side of the thermal network (Eq. 3): the gain P·R2 and the
// slow time constant R2·C2 show at every power switch. The junction's side shows in the case
// temperature only through the small delay it adds to a switch: its rise above the case while
// on, P·R1, and its time constant R1·C1. The datasheet-prior fit (core/thermal_map_fit.hpp)
// therefore usually holds them at the datasheet, and a device whose junction is hotter or slower
// than the datasheet's gets a junction estimate (Eq. 7) that is wrong for a few R1·C1 after every
// power-on. The ranges see exactly that: after a power-on the junction climbs P·R1 above the case
// over a few R1·C1, and the bias H(t^j)θ of Eq. 8 climbs with it.
//
// So training completes the thermal fit with the ranges. With x = (log P·R1, log R1·C1) and P, R2,
// C2 held where the case-log fit put them (R1 = P·R1 / P, C1 = R1·C1 / R1), it maximizes
//
//   L(x) = ℓ_ranges(x) + log prior(x),
//
// ℓ_ranges: Eq. 8's log-likelihood of the training ranges at the junction smoothed with x (Eq. 7),
//   maximized over θ and the mixture by EM (§5) at the chosen structure (basis family and order,
//   number of modes), warm-started from the previous point's fit; the basis keeps its terms and is
//   rescaled to the junction temperatures of each x;
// log prior: the datasheet's log-normal prior on R1 and C1, as the case-log fit has it
//   (core/thermal_map_fit.hpp: ln 2 at one σ by default).
// The case log's own likelihood is left out: along these directions its information is below
// what the case-log fit trusts (it holds them at the datasheet for that reason: a sensor's lag or
// an ambient logged coarsely drags them), and adding it back lets that drag in again (on the twin
// with a coarse sensor it pulled P·R1 to 6 K for a 4.5 K device while the ranges lost).
//
// The search: Nelder-Mead on the two log coordinates (the posterior's ridge runs diagonally: a
// larger rise with a slower time constant looks alike at a switch), over a box
// of ±kSearchPriorSigmas prior standard deviations of each product around the datasheet's value:
// a junction the prior calls implausible is not reached for, so a slow effect of another origin
// (a warm-up of minutes, a drift) cannot be absorbed into a junction time constant of minutes.
// The answer replaces the case-log fit's only when the ranges reject the latter: when the ranges'
// gain, summed over blocks of kJunctionBlockRanges consecutive ranges, is positive by a
// one-sided t-test on the blocks at rejection_level. The blocks, not the ranges, are the units:
// the junction estimate's errors are slow, so the ranges are not independent given it, and a
// likelihood-ratio test counting each range as news rejects a device whose junction is the
// datasheet's (on the twin with a coarse sensor, 2Δℓ of 10-36 against χ²(2)'s 9.2 at 1 %, on
// three draws of three). Otherwise the case-log fit stands, as the Kalman filter's noise levels
// keep their LMS 200 values unless the log rejects them.
//
// The junction's process noise q_j is judged by the ranges too. The case log sets the filter's
// levels by its innovations' likelihood (core/kalman_noise_fit.hpp), but it sees the junction
// only through the case, and what it takes for junction noise may be its own misfit: a sensor
// whose noise is small against its resolution (0.01 °C under 0.1 °C steps) reads a slow case as
// a staircase, whose rounding errors are correlated over many readings; the filter, which takes
// them for white, explains them by a junction that wanders (a blind draw's case log moved q_j
// from 1e-4 to 0.096 K²/s, and its junction estimate wandered ±1.3 K around the true one in the
// steady state, where the true junction is the case plus a constant). So when the case log
// raised q_j above its start, the junction at the case-log fit's dynamics is evaluated once more
// with q_j back at its start, and the ranges judge the move by the same blocks' t-test: they hold
// q_j at its start when they reject the case log's level, and the search then runs with it. (A
// q_j the log lowered has the junction follow the thermal model, the case-log fit's own junction,
// and is not asked about: on the twin's default record, asked, the t-test held 1e-4 against the
// log's 2.4e-7 on a gain of 0.5 nats, and the search then moved the datasheet's junction,
// 1.8 K and 10.8 s, to 1.2 K and 11 s.)
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "core/basis.hpp"
#include "core/em_train.hpp"
#include "core/kalman.hpp"
#include "core/kalman_noise_fit.hpp"
#include "core/thermal_map_fit.hpp"

namespace tofcomp::calibration {

// The junction's side of the thermal network (Eq. 3).
struct JunctionDynamics {
  double rise_k = 0.0;           // P·R1: the junction's steady rise above the case while on
  double time_constant_s = 0.0;  // R1·C1
};
JunctionDynamics junction_dynamics_of(const core::ThermalParameters& parameters);
// `parameters` with R1 and C1 set so that its junction has `dynamics`; P, R2 and C2 kept.
core::ThermalParameters with_junction_dynamics(const core::ThermalParameters& parameters,
                                               const JunctionDynamics& dynamics);

struct JunctionDynamicsOptions {
  // The t-test's level: the case-log fit's junction is replaced only when the ranges reject it
  // at this level.
  double rejection_level = 0.05;
  // Nelder-Mead on the log coordinates: the first simplex's step (log units), and the stops: the
  // simplex's values within value_tolerance (nats) of each other, or its extent below
  // log_tolerance, or max_evaluations points fitted.
  double initial_log_step = 0.5;
  double value_tolerance = 0.05;
  double log_tolerance = 0.01;
  int max_evaluations = 60;
  // The EM fits' options (the structure search's, looser than the final fit's).
  core::EmTrainOptions em;
  // Throws InvalidInput naming the first bad option.
  void validate() const;
};

// The ranges of one block of the t-test.
inline constexpr Eigen::Index kJunctionBlockRanges = 200;

// One point the search evaluated.
struct JunctionDynamicsPoint {
  JunctionDynamics dynamics;
  double ranges_log_likelihood = 0.0;  // ℓ_ranges
  double prior_cost = 0.0;             // −log prior (up to a constant)
  Eigen::VectorXd block_log_likelihood;  // ℓ_ranges over each block of kJunctionBlockRanges
  double log_posterior() const { return ranges_log_likelihood - prior_cost; }
};

struct JunctionDynamicsFit {
  JunctionDynamics datasheet;  // the prior's centre
  JunctionDynamicsPoint start;  // the case-log fit's junction
  JunctionDynamicsPoint best;   // the search's answer
  bool replaced = false;        // best replaced start (the test rejected start, or see below)
  // best replaced start though the test did not reject it: asked for (JunctionSource::Ranges),
  // as the junction re-check's alternative, because its posterior is above start's.
  bool replaced_untested = false;
  // Whether best, not taken, has a posterior above start's: the alternative the junction
  // re-check may judge.
  bool ranges_answer_above_start() const;
  // Takes best in place of start where ranges_answer_above_start().
  void take_ranges_answer();
  // Training's final fit failed on the junction from the ranges (its error): start was kept
  // although the test rejected it, and replaced is false.
  std::string refused_by_final_fit;
  double block_t = 0.0;            // the blocks' t statistic of the ranges' gain
  double block_p = 1.0;            // its one-sided p-value
  JunctionDynamicsPoint chosen() const { return replaced ? best : start; }
  // The filter's levels of the case log, and the junction at start's dynamics with q_j back at
  // its start when the case log had raised it (JunctionDynamicsProblem::held_junction_noise).
  core::ThermalNoise case_log_noise;
  std::optional<core::ThermalNoise> held_junction_noise;
  std::optional<JunctionDynamicsPoint> held_junction_noise_start;
  double noise_block_t = 0.0;  // that junction's gain over start's, over the same blocks
  double noise_block_p = 1.0;
  // The ranges rejected the case log's q_j: the search ran with q_j held at its start.
  bool junction_noise_held = false;
  // The chosen junction's filter holds q_j at its start: the ranges rejected the case log's
  // level, and the search's answer replaced the case-log fit's junction.
  bool chosen_holds_junction_noise() const { return replaced && junction_noise_held; }
  // The levels of the chosen junction's filter: the calibration's.
  core::ThermalNoise chosen_noise() const {
    return chosen_holds_junction_noise() ? *held_junction_noise : case_log_noise;
  }
  // In the order evaluated: the search's points and, second, the q_j alternative when there is
  // one (best is the best of the points at the q_j the search ran with).
  std::vector<JunctionDynamicsPoint> evaluated;
};

// What the search needs of training: the data, the case-log fit, the filter's noise levels and
// the structure chosen for Eq. 8.
struct JunctionDynamicsProblem {
  const MeasuredData& data;
  const core::MapFitResult& case_fit;
  const core::MapFitOptions& case_fit_options;
  core::ThermalNoise kalman_noise;  // the case log's levels
  // kalman_noise with q_j back at the level the case log's fit started from, when that fit
  // raised it (training's choice; any level may be judged here).
  std::optional<core::ThermalNoise> held_junction_noise;
  double ambient_fallback_c = 22.0;
  core::Basis basis;  // its terms are kept; its scaling follows each point's junction
  int modes = 2;
  core::EmStartingPoint start;  // the structure search's fit at the case-log fit's junction
};

// The case log's levels with q_j back where their fit started, when that fit raised it: the
// alternative the ranges judge (JunctionDynamicsProblem::held_junction_noise). Absent when the
// fit held or lowered q_j: a lower q_j has the junction follow the thermal model, the case-log
// fit's own junction, which the search judges already; a higher one lets it follow the case
// readings' misfit, which is what the ranges guard against.
std::optional<core::ThermalNoise> held_junction_noise(const core::KalmanNoiseFit& fit);

using JunctionDynamicsProgress = std::function<void(const JunctionDynamicsPoint&)>;

// The search of the header. Throws core::Error when the start's fit fails; a point whose EM fit
// fails scores −∞ and is not chosen.
JunctionDynamicsFit fit_junction_dynamics(const JunctionDynamicsProblem& problem,
                                          const JunctionDynamicsOptions& options,
                                          const JunctionDynamicsProgress& progress = {});

// An EM start for H at `mixture`: θ by least squares of the ranges less the mixture's mean
// offset Σ π_i μ_i (for a design whose columns changed meaning, e.g. rescaled).
core::EmStartingPoint least_squares_start(const Eigen::MatrixXd& h,
                                          const Eigen::VectorXd& y_minus_d,
                                          const core::MixtureParameters& mixture);

// The basis's terms rescaled to junction temperatures (Legendre terms span them; Fourier terms
// keep their fundamental).
core::Basis basis_spanning(const core::Basis& basis, const Eigen::VectorXd& junction_c);

}  // namespace tofcomp::calibration
