// Classical tests the residual diagnosis uses, each returning its statistic and p-value.
// Pure functions on vectors; the distributions' tails are Boost.Math's, and in logs where the
// probability is too small for a double (so that z stays finite far in the tail).
#pragma once

#include <Eigen/Core>

namespace tofcomp::core {

struct TestResult {
  double statistic = 0.0;
  double p_value = 1.0;
  double degrees_of_freedom = 0.0;  // where the reference law has them
  // The statistic on a common scale: the standard-normal deviate with the same upper tail
  // (Wilson–Hilferty for χ²), so findings can be ranked where p-values underflow to 0.
  double z = 0.0;
};

// The standard-normal deviate of a χ²_df statistic (Wilson and Hilferty, 1931).
double chi_square_to_z(double x, double df);

// Q(a, x) = Γ(a, x) / Γ(a), the regularized upper incomplete gamma function (a > 0, x ≥ 0).
double regularized_upper_gamma(double a, double x);
// P(χ²_df > x).
double chi_square_survival(double x, double df);
// P(|N(0,1)| > |z|).
double two_sided_normal_p(double z);
// P(T ≥ t) for Student's T with df degrees of freedom (0 at t = +∞, 1 at −∞).
double student_upper_tail(double t, double df);

// Ljung–Box: Q = n(n+2) Σ_{k=1..h} ρ_k² / (n − k) against χ²_h; small p: serial dependence.
TestResult ljung_box(const Eigen::Ref<const Eigen::VectorXd>& series, int lags);

// Wald–Wolfowitz runs test on a two-valued sequence (labels 0/1): the number of runs against
// its mean 2 n0 n1 / n + 1 and variance; statistic z (negative: fewer runs, i.e. persistence).
TestResult runs_test(const Eigen::Ref<const Eigen::VectorXi>& labels);

// Pearson correlation of x and y with the large-sample test z = r √(n − 2) / √(1 − r²)
// (approximately normal for the sample sizes here); statistic = r.
TestResult correlation_test(const Eigen::Ref<const Eigen::VectorXd>& x,
                            const Eigen::Ref<const Eigen::VectorXd>& y);
// The same test of a correlation r already computed from n pairs.
TestResult correlation_result(double r, Eigen::Index n);

// The most significant of several correlation tests of y, one per candidate x (the columns),
// with Bonferroni's correction for having picked it: p = min(1, columns × p_best), z the
// two-sided deviate of that p (finite far in the tail). statistic = r of the best column. A
// family of covariates indexed by a parameter the data must choose (a time constant) is tested
// this way.
TestResult best_correlation_test(const Eigen::Ref<const Eigen::MatrixXd>& x_columns,
                                 const Eigen::Ref<const Eigen::VectorXd>& y);

// log P(N(0,1) > z), exact while representable, else the asymptotic series.
double log_upper_normal_tail(double z);

// Likelihood-ratio test of a nested extension: 2 (ℓ1 − ℓ0) against χ²_df.
TestResult likelihood_ratio_test(double log_likelihood_null, double log_likelihood_alternative,
                                 int extra_parameters);

// The split likelihood-ratio test of universal inference (Wasserman, Ramdas and Balakrishnan,
// PNAS 2020): the alternative fitted on one half of the data, its likelihood on the other half
// against the null's maximum there, T = L₀(θ̂₁) / L₀(θ̂₀), averaged over both directions. Valid
// at any sample size without regularity conditions (so for the number of mixture components,
// where 2Δℓ is not χ²): P(T ≥ 1/α) ≤ α. statistic = log T, p = min(1, 1/T).
TestResult split_likelihood_ratio_test(double log_t);

// The standard-normal deviate whose upper tail is exp(log_p) (log_p ≤ 0), also where the
// p-value itself underflows.
double normal_deviate_of_log_p(double log_p);

// Pearson χ² test of independence of a contingency table of counts (rows × columns).
TestResult chi_square_independence(const Eigen::Ref<const Eigen::MatrixXd>& counts);

// Excess of extreme values: of n values, `observed` beyond a bound that each exceeds with
// probability `tail_probability` under the model; one-sided test with the Poisson law of the
// count (n large, the probability small), exact and in logs, so z stays finite far in the
// tail; statistic = observed / expected.
TestResult tail_excess_test(double observed, double n, double tail_probability);

}  // namespace tofcomp::core
