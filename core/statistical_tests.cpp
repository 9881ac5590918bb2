#include "core/statistical_tests.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// Below this a probability is not represented well enough to take its log: the tails are then
// computed in logs (the Poisson series, the normal tail's asymptotic series).
constexpr double kSmallestProbability = 1e-300;
// The far Poisson tail's series: its terms' cap and relative tolerance.
constexpr int kMaxSeriesTerms = 10000;
constexpr double kSeriesTolerance = 1e-17;

}  // namespace

double regularized_upper_gamma(double a, double x) {
  require_positive(a, "gamma shape a");
  if (!(x >= 0.0) || !std::isfinite(x)) throw InvalidInput("gamma argument x must be >= 0");
  return boost::math::gamma_q(a, x);
}

double chi_square_survival(double x, double df) {
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(df), std::max(0.0, x)));
}

double student_upper_tail(double t, double df) {
  if (std::isinf(t)) return t > 0.0 ? 0.0 : 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::students_t(df), t));
}

double chi_square_to_z(double x, double df) {
  const double v = 2.0 / (9.0 * df);
  return (std::cbrt(std::max(x, 0.0) / df) - (1.0 - v)) / std::sqrt(v);
}

double two_sided_normal_p(double z) {
  return 2.0 * boost::math::cdf(boost::math::complement(boost::math::normal(), std::abs(z)));
}

TestResult ljung_box(const Eigen::Ref<const Eigen::VectorXd>& series, int lags) {
  const Eigen::Index n = series.size();
  require_finite(series, "series");
  if (lags < 1 || lags >= n) throw InvalidInput("Ljung-Box needs 1 <= lags < n");
  const Eigen::ArrayXd centred = series.array() - series.mean();
  const double variance = centred.square().sum();
  if (!(variance > 0.0)) throw NumericalError("Ljung-Box on a constant series");
  double q = 0.0;
  for (int k = 1; k <= lags; ++k) {
    const double rho = (centred.head(n - k) * centred.tail(n - k)).sum() / variance;
    q += rho * rho / static_cast<double>(n - k);
  }
  q *= static_cast<double>(n) * static_cast<double>(n + 2);
  return {q, chi_square_survival(q, lags), static_cast<double>(lags), chi_square_to_z(q, lags)};
}

TestResult runs_test(const Eigen::Ref<const Eigen::VectorXi>& labels) {
  const Eigen::Index n = labels.size();
  double n1 = 0.0;
  double runs = n > 0 ? 1.0 : 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (labels[k] != 0 && labels[k] != 1) throw InvalidInput("runs test labels must be 0 or 1");
    n1 += labels[k];
    if (k > 0 && labels[k] != labels[k - 1]) runs += 1.0;
  }
  const double n0 = static_cast<double>(n) - n1;
  if (n0 < 2 || n1 < 2) throw NumericalError("runs test needs at least two of each label");
  const double total = static_cast<double>(n);
  const double mean = 2.0 * n0 * n1 / total + 1.0;
  const double variance = 2.0 * n0 * n1 * (2.0 * n0 * n1 - total) / (total * total * (total - 1.0));
  const double z = (runs - mean) / std::sqrt(variance);
  return {z, two_sided_normal_p(z), 0.0, std::abs(z)};
}

TestResult correlation_test(const Eigen::Ref<const Eigen::VectorXd>& x,
                            const Eigen::Ref<const Eigen::VectorXd>& y) {
  require_same_length(x.size(), "x", y.size(), "y");
  require_finite(x, "x");
  require_finite(y, "y");
  const Eigen::Index n = x.size();
  if (n < 4) throw InvalidInput("a correlation test needs at least four pairs");
  const Eigen::ArrayXd dx = x.array() - x.mean();
  const Eigen::ArrayXd dy = y.array() - y.mean();
  const double sxx = dx.square().sum();
  const double syy = dy.square().sum();
  if (!(sxx > 0.0) || !(syy > 0.0)) return {0.0, 1.0, 0.0};
  return correlation_result((dx * dy).sum() / std::sqrt(sxx * syy), n);
}

TestResult correlation_result(double r, Eigen::Index n) {
  if (n < 4) throw InvalidInput("a correlation test needs at least four pairs");
  r = std::clamp(r, -1.0, 1.0);
  const double denominator = std::max(1.0 - r * r, 1e-300);
  const double z = r * std::sqrt(static_cast<double>(n - 2) / denominator);
  return {r, two_sided_normal_p(z), static_cast<double>(n - 2), std::abs(z)};
}

TestResult best_correlation_test(const Eigen::Ref<const Eigen::MatrixXd>& x_columns,
                                 const Eigen::Ref<const Eigen::VectorXd>& y) {
  if (x_columns.cols() < 1) throw InvalidInput("a best-correlation test needs a candidate");
  TestResult best;
  for (Eigen::Index c = 0; c < x_columns.cols(); ++c) {
    const TestResult r = correlation_test(x_columns.col(c), y);
    if (c == 0 || r.z > best.z) best = r;
  }
  // Two-sided: p = 2 Q(z); corrected, Q(z') = columns × Q(z).
  const double log_tail = std::log(static_cast<double>(x_columns.cols())) +
                          log_upper_normal_tail(best.z);
  best.p_value = std::min(1.0, 2.0 * std::exp(log_tail));
  best.z = normal_deviate_of_log_p(log_tail);
  return best;
}

TestResult likelihood_ratio_test(double log_likelihood_null, double log_likelihood_alternative,
                                 int extra_parameters) {
  require_finite(log_likelihood_null, "null log-likelihood");
  require_finite(log_likelihood_alternative, "alternative log-likelihood");
  if (extra_parameters < 1) throw InvalidInput("a likelihood-ratio test needs extra parameters");
  const double statistic = std::max(0.0, 2.0 * (log_likelihood_alternative - log_likelihood_null));
  return {statistic, chi_square_survival(statistic, extra_parameters),
          static_cast<double>(extra_parameters), chi_square_to_z(statistic, extra_parameters)};
}

TestResult chi_square_independence(const Eigen::Ref<const Eigen::MatrixXd>& counts) {
  require_finite(counts, "contingency counts");
  const double total = counts.sum();
  if (!(total > 0.0)) throw InvalidInput("an empty contingency table");
  const Eigen::VectorXd rows = counts.rowwise().sum();
  const Eigen::RowVectorXd cols = counts.colwise().sum();
  double statistic = 0.0;
  int used_rows = 0, used_cols = 0;
  for (Eigen::Index r = 0; r < counts.rows(); ++r) used_rows += rows[r] > 0.0;
  for (Eigen::Index c = 0; c < counts.cols(); ++c) used_cols += cols[c] > 0.0;
  for (Eigen::Index r = 0; r < counts.rows(); ++r) {
    for (Eigen::Index c = 0; c < counts.cols(); ++c) {
      const double expected = rows[r] * cols[c] / total;
      if (expected > 0.0)
        statistic += (counts(r, c) - expected) * (counts(r, c) - expected) / expected;
    }
  }
  const int df = (used_rows - 1) * (used_cols - 1);
  if (df < 1) return {0.0, 1.0, 0.0};
  return {statistic, chi_square_survival(statistic, df), static_cast<double>(df),
          chi_square_to_z(statistic, df)};
}

TestResult tail_excess_test(double observed, double n, double tail_probability) {
  if (!(n > 0.0) || !(tail_probability > 0.0 && tail_probability < 1.0) || observed < 0.0) {
    throw InvalidInput("tail excess test needs n > 0, 0 < p < 1, observed >= 0");
  }
  const double lambda = n * tail_probability;
  const double k = std::floor(observed);
  // log P(X ≥ k), X ~ Poisson(λ); beyond its expectation (k > λ), where the probability may be
  // too small for a double, the far tail's series e^{−λ} λ^k / k! Σ_m λ^m k! / (k + m)!, in
  // logs, so that a count far beyond its expectation keeps a finite z instead of a p-value of 0.
  double log_p = 0.0;
  if (k > 0.0) {
    if (k > lambda) {
      double term = 1.0, sum = 1.0;
      for (int m = 1; m < kMaxSeriesTerms && term > kSeriesTolerance * sum; ++m) {
        term *= lambda / (k + m);
        sum += term;
      }
      log_p = -lambda + k * std::log(lambda) - std::lgamma(k + 1.0) + std::log(sum);
    } else {
      // At or below its expectation the count's tail is not small: P(X ≥ k) = P(k, λ), the
      // regularized lower incomplete gamma function.
      log_p = std::log(std::max(boost::math::gamma_p(k, lambda), kSmallestProbability));
    }
  }
  TestResult r;
  r.statistic = observed / lambda;
  r.p_value = std::exp(log_p);
  r.z = log_p < std::log(0.5) ? normal_deviate_of_log_p(log_p) : 0.0;
  return r;
}

double log_upper_normal_tail(double z) {
  const double tail = boost::math::cdf(boost::math::complement(boost::math::normal(), z));
  if (tail > kSmallestProbability) return std::log(tail);
  return -0.5 * z * z - std::log(z * std::sqrt(2.0 * std::numbers::pi)) +
         std::log1p(-1.0 / (z * z));
}

double normal_deviate_of_log_p(double log_p) {
  if (log_p >= std::log(0.5)) return 0.0;
  if (log_p > std::log(kSmallestProbability)) {
    return boost::math::quantile(boost::math::complement(boost::math::normal(), std::exp(log_p)));
  }
  // Beyond what a double holds as a probability: Newton on the asymptotic log tail.
  double z = std::sqrt(-2.0 * log_p);
  for (int i = 0; i < 60; ++i) {
    // d/dz log Q(z) = −φ(z)/Q(z) ≈ −(z + 1/z) for large z; Newton on log Q.
    const double f = log_upper_normal_tail(z) - log_p;
    const double h = 1e-6 * std::max(1.0, z);
    const double slope = (log_upper_normal_tail(z + h) - log_upper_normal_tail(z - h)) / (2.0 * h);
    const double step = f / slope;
    z = std::max(z - step, 1e-9);
    if (std::abs(step) < 1e-10 * std::max(1.0, z)) break;
  }
  return z;
}

TestResult split_likelihood_ratio_test(double log_t) {
  TestResult r;
  r.statistic = log_t;
  r.p_value = log_t > 0.0 ? std::exp(-log_t) : 1.0;
  r.z = log_t > 0.0 ? normal_deviate_of_log_p(-log_t) : 0.0;
  return r;
}

}  // namespace tofcomp::core
