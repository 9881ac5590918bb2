// The grammar of what Eq. 8 may lack: any parameter of the model (the bias, one mode's offset,
// the modes' spreads, the modes' weights) may depend on any covariate the data carry, in one of
// a few forms, and the model's structure may grow (the modes a Markov chain, one more mode, an
// outlier component). One term of the grammar is "parameter × covariate × form"; the model
// search (calibration/model_search.hpp) enumerates them, fits each by the closed-form EM of
// core/extended_em.hpp and judges it on held-out ranges. The paper's model (§4) is the grammar's
// empty sentence: y_k = d + H(t^j_k)θ + w_k with fixed modes.
//
//   parameter      forms                       what a term adds to Eq. 8
//   bias           linear, smooth, decay        Σ_c γ_c f(c_k): one or a few design columns
//   mode offset    linear, decay                μ_i + β f(c_k) for one mode i
//   spread         bins, linear, decay          σ²_i per bin, or log σ²_i + s_i f(c_k)
//   weights        bins, linear, decay          π_i per bin, or log-odds a_i + b_i f(c_k)
//   markov         -                            the mode a Markov chain (transition matrix A)
//   extra mode     -                            M + 1 modes
//   outliers       -                            a uniform component of weight ε
//
// The forms: linear, f(c) = (c − c̄)/s (standardized; for a mean term held constant beyond the
// covariate's range on the data it was fitted on); smooth, piecewise-linear hat functions on
// knots at the covariate's quantiles (constant beyond the end knots: a linear time drift is the
// one form carried on beyond its data, which the future always exceeds); decay, exp(−c/τ) with τ
// profiled by the search; bins, a parameter value per quantile bin. A spread or weights term of
// the linear or decay form is evaluated on kNoiseLevels levels of f, equally spaced between its
// extremes on the data (its knots are the levels' edges in the covariate's units): within
// 1/(2 kNoiseLevels) of f's span of the exact value, and the E-step, the daemon and the file keep
// one table per level, as for bins.
//
// The covariates, at each range: the junction temperature t̂^j (§3.3), its heating rate
// (°C/min), the time since the last power-on, the time since the start (h), the logged ambient,
// and the junction's lag, L_τ(t̂^j) − t̂^j with L_τ a first-order low-pass of time constant τ
// (profiled): a temperature node the two-state network of §3 lacks, driven by the junction (a
// bias term on it is the grammar's "another thermal state"). The case temperature is not one:
// while the laser ranges, t̂^j is the case reading plus the junction's rise over it, so a
// dependence on the case temperature is one on t̂^j.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>

namespace tofcomp::core {

enum class Parameter { Bias, ModeOffset, Spread, Weights, Markov, ExtraMode, Outliers };
enum class Covariate {
  None,
  JunctionTemperature,  // °C
  HeatingRate,          // °C/min
  TimeSincePowerOn,     // s
  Time,                 // h since the start of the data
  Ambient,              // °C
  JunctionLag,          // °C: L_τ(t̂^j) − t̂^j
};
enum class Form { None, Linear, Smooth, Decay, Bins };

inline constexpr std::array<Covariate, 6> kCovariates{
    Covariate::JunctionTemperature, Covariate::HeatingRate, Covariate::TimeSincePowerOn,
    Covariate::Time,                Covariate::Ambient,     Covariate::JunctionLag};

// Tokens (files, JSON) and back; the parse functions throw InvalidInput naming the token.
const char* parameter_token(Parameter p);     // "bias", "mode_offset", ...
const char* covariate_token(Covariate c);     // "junction_temperature", ...
const char* form_token(Form f);               // "linear", "smooth", "decay", "bins", "none"
Parameter parse_parameter(const std::string& token);
Covariate parse_covariate(const std::string& token);
Form parse_form(const std::string& token);
const char* covariate_unit(Covariate c);      // "°C", "°C/min", "s", "h", ...

// What a term says about the scanner, as a user reads it and as the blind scorer compares it:
// the parameter and the covariate (the form is how it is approximated). A bias on the junction's
// lag is "another thermal state" (parameter token "thermal_state", no covariate).
struct EffectLabel {
  Parameter parameter = Parameter::Bias;
  Covariate covariate = Covariate::None;
  bool operator==(const EffectLabel&) const = default;
};
std::string label_parameter_token(const EffectLabel& label);  // "thermal_state" for the lag
std::string label_covariate_token(const EffectLabel& label);  // "none" for the lag
// A name for people: "time drift", "warm-up after power-on", "temperature-dependent weights",
// "spread depends on the time since power-on", ...
std::string effect_name(const EffectLabel& label);

// The τ of a decay or of the junction's lag is profiled over this logarithmic grid and refined
// between the best point's neighbours.
inline constexpr std::array<double, 7> kTimeConstantGridS{30.0,  60.0,  120.0, 240.0,
                                                          480.0, 960.0, 1920.0};
// Knots of the smooth form and bins of the bins form, at the covariate's quantiles. The smooth
// form is a candidate at each count of kSmoothKnotCounts (the search judges them on held-out data
// like any two candidates: a drift that turns many times needs many knots, a gentle one is
// over-fitted by them); each count's quantiles hold the one before's, so their models are nested.
// A term's count is its knots' (a file may hold any count from the first to the last).
inline constexpr std::array<int, 4> kSmoothKnotCounts{3, 5, 9, 17};
inline constexpr int kMinSmoothKnots = kSmoothKnotCounts.front();
inline constexpr int kMaxSmoothKnots = kSmoothKnotCounts.back();
inline constexpr int kCovariateBins = 4;
inline constexpr int kNoiseLevels = 24;

// One term of the grammar with what defines its design, but no fitted value: the candidate a
// search fits. `mode` names the mode of a mode-offset term (0-based); `time_constant_s` the τ of a
// decay or of the junction's lag; `knots` the smooth form's knots or the bins' interior edges;
// `centre` and `scale` standardize a linear covariate.
struct Term {
  Parameter parameter = Parameter::Bias;
  Covariate covariate = Covariate::None;
  Form form = Form::None;
  int mode = -1;
  double time_constant_s = 0.0;
  Eigen::VectorXd knots;
  double centre = 0.0;
  double scale = 1.0;
  // A linear mean term's covariate range on the ranges it was fitted on: beyond it f holds its
  // value at the nearer end, as the smooth form does beyond its end knots, so a slope fitted on
  // the bulk of a covariate is not carried out to values it never saw (a heating rate's slope
  // fitted between 0.015 and 0.1 °C/min, carried to a power-on's 2.5 °C/min, moved those ranges
  // by tens of millimetres). Infinite: unbounded (a file written before the bound, and a drift in
  // time, whose covariate always leaves the range it was fitted on).
  double covariate_low = -std::numeric_limits<double>::infinity();
  double covariate_high = std::numeric_limits<double>::infinity();
  bool has_covariate_range() const {  // held beyond a finite range
    return covariate_low > -std::numeric_limits<double>::infinity() &&
           covariate_high < std::numeric_limits<double>::infinity();
  }

  EffectLabel label() const { return {parameter, covariate}; }
  bool is_mean_term() const {  // adds design columns (bias, a mode's offset)
    return parameter == Parameter::Bias || parameter == Parameter::ModeOffset;
  }
  bool is_noise_term() const {  // a table per bin or level (spread, weights)
    return parameter == Parameter::Spread || parameter == Parameter::Weights;
  }
  // A noise term whose table follows a slope on f(c) (linear, decay) rather than free bins.
  bool is_parametric_noise() const { return is_noise_term() && form != Form::Bins; }
  bool needs_time_constant() const {
    return form == Form::Decay || covariate == Covariate::JunctionLag;
  }
  // Design columns of a mean term: 1 (linear, decay) or its knots − 1 (smooth).
  int columns() const;
  // The bins or levels of a noise term (its knots + 1).
  int levels() const { return static_cast<int>(knots.size()) + 1; }
  // "bias × time since power-on (decay, τ = 300 s)", "bias × time (smooth, 9 knots)".
  std::string describe() const;
  // Throws InvalidInput naming what is inconsistent (a form the parameter does not take, a
  // missing mode, knots not increasing, τ not positive, ...).
  void validate() const;
};

}  // namespace tofcomp::core
