// The covariates of the grammar (core/effect_grammar.hpp) at each range of a record, and the
// design of a term on them: a mean term's columns, a noise term's bins. Offline the junction
// temperature is the smoother's (§3.3, Eq. 7) and its history covers the power-off gaps too, so
// that the junction's lag L_τ(t̂^j) − t̂^j cools through a gap as the node would.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/effect_grammar.hpp"

namespace tofcomp::core {

// A series that brings no heating rate of its own (one without a thermal model) gets the slope
// of its junction over ±30 s around each range.
inline constexpr double kHeatingRateHalfWindowS = 30.0;

struct CovariateSeries {
  Eigen::VectorXd time_s;                 // of each range, s
  Eigen::VectorXd junction_c;             // t̂^j at each range
  Eigen::VectorXd time_since_power_on_s;  // at each range
  Eigen::VectorXd ambient_c;              // at each range; empty when the data log none
  // dt̂^j/dt at each range in °C/min, from the thermal model (calibration/junction_estimate.hpp);
  // empty: the slope of junction_c over ±kHeatingRateHalfWindowS.
  Eigen::VectorXd heating_rate_c_per_min;
  // The junction's estimate over the whole record (power-off included) and each range's index in
  // it; empty: the lag runs over the ranges' own instants.
  Eigen::VectorXd history_time_s;
  Eigen::VectorXd history_junction_c;
  Eigen::VectorXi range_in_history;
};

class CovariateTable {
 public:
  // Throws InvalidInput on mismatched lengths, non-finite values, time going back or a history
  // index out of range.
  explicit CovariateTable(CovariateSeries series);

  Eigen::Index size() const { return series_.time_s.size(); }
  // Every covariate but the ambient, which needs a logged ambient.
  bool available(Covariate c) const;
  // The covariate at each range (the junction's lag at time constant τ). Throws InvalidInput
  // for a covariate that is not available.
  Eigen::VectorXd values(Covariate c, double time_constant_s = 0.0) const;

  // A term of the grammar fitted to these data's covariate over `rows` (all when empty): the
  // smooth form's `smooth_knots` knots and the bins' edges at its quantiles, the linear form's
  // centre and scale. Throws InvalidInput when the covariate has too few distinct values for the
  // form.
  Term make_term(Parameter parameter, Covariate covariate, Form form, int mode = -1,
                 double time_constant_s = 0.0, const std::vector<Eigen::Index>& rows = {},
                 int smooth_knots = kMinSmoothKnots) const;
  // The term's design columns at every range (K × term.columns()), or its bin of every range.
  Eigen::MatrixXd columns(const Term& term) const;
  Eigen::VectorXi bins(const Term& term) const;

 private:
  Eigen::VectorXd junction_lag(double time_constant_s) const;

  CovariateSeries series_;
  Eigen::VectorXd heating_rate_c_per_min_;
};

// One term's design at one covariate value: its columns (term.columns() of them) or its bin.
// The daemon evaluates terms this way, scan by scan.
// f at each level of a parametric noise term (linear or decay): the middle of the level's span
// of f (the end levels as wide as their neighbours).
Eigen::VectorXd noise_level_values(const Term& term);
void term_design_row(const Term& term, double covariate_value, Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row);
int term_bin(const Term& term, double covariate_value);

// The time derivative of a sampled signal by least-squares slopes over ±half_window_s around
// each sample (the junction's heating rate from its smoothed estimate). O(K).
Eigen::VectorXd local_rate(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                           const Eigen::Ref<const Eigen::VectorXd>& value, double half_window_s);

// L_τ(x): a first-order low-pass of time constant τ over irregular samples (the input held at
// the mean of each interval's ends), starting at rest at x_0. The lag's node.
Eigen::VectorXd first_order_lag(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                const Eigen::Ref<const Eigen::VectorXd>& value,
                                double time_constant_s);

}  // namespace tofcomp::core
