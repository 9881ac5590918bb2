#include "core/gaussian_mixture.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr double kWeightSumTolerance = 1e-9;

// log π_i − ½ log(2π σ_i²) − (e − μ_i)² / (2σ_i²) for every sample (rows) and mode (columns).
void log_joint(const Eigen::Ref<const Eigen::VectorXd>& residual, const MixtureParameters& m,
               Eigen::MatrixXd& out) {
  const Eigen::Index k = residual.size();
  out.resize(k, m.modes());
  for (int i = 0; i < m.modes(); ++i) {
    const double log_weight =
        m.weight[i] > 0.0 ? std::log(m.weight[i]) : -std::numeric_limits<double>::infinity();
    const double log_norm = -0.5 * std::log(2.0 * std::numbers::pi * m.variance[i]);
    const double inv_two_var = 0.5 / m.variance[i];
    out.col(i) = ((residual.array() - m.mean[i]).square() * -inv_two_var) + (log_weight + log_norm);
  }
}

// P(a ≤ Z < b) for a standard normal Z, from the tail on the side of the interval, so that an
// interval far out in a tail keeps its relative accuracy.
double standard_normal_interval(double a, double b) {
  const auto upper_tail = [](double z) { return 0.5 * std::erfc(z / std::numbers::sqrt2); };
  if (a >= 0.0) return upper_tail(a) - upper_tail(b);
  if (b <= 0.0) return upper_tail(-b) - upper_tail(-a);
  return 1.0 - upper_tail(b) - upper_tail(-a);
}

}  // namespace

void MixtureParameters::validate() const {
  if (mean.size() < 1 || variance.size() != mean.size() || weight.size() != mean.size()) {
    std::ostringstream msg;
    msg << "mixture has " << mean.size() << " means, " << variance.size() << " variances and "
        << weight.size() << " weights: it needs one of each per mode, at least one mode";
    throw InvalidInput(msg.str());
  }
  require_finite(mean, "mode mean");
  require_finite(variance, "mode variance");
  require_finite(weight, "mode weight");
  for (int i = 0; i < modes(); ++i) {
    if (!(variance[i] > 0.0)) {
      std::ostringstream msg;
      msg << "mode " << i + 1 << " has variance " << variance[i] << ": it must be positive";
      throw InvalidInput(msg.str());
    }
    if (weight[i] < 0.0 || weight[i] > 1.0) {
      std::ostringstream msg;
      msg << "mode " << i + 1 << " has weight " << weight[i] << ": it must be in [0, 1]";
      throw InvalidInput(msg.str());
    }
  }
  if (std::abs(weight.sum() - 1.0) > kWeightSumTolerance) {
    std::ostringstream msg;
    msg << "mode weights sum to " << weight.sum() << ": they must sum to 1";
    throw InvalidInput(msg.str());
  }
}

double mixture_e_step(const Eigen::Ref<const Eigen::VectorXd>& residual,
                      const MixtureParameters& mixture, Eigen::MatrixXd& responsibilities) {
  log_joint(residual, mixture, responsibilities);
  // Log-sum-exp per range, on the modes' columns (vectorized max, exp and log over the ranges).
  const int m = mixture.modes();
  auto joint = responsibilities.array();
  Eigen::ArrayXd top = joint.col(0);
  for (int i = 1; i < m; ++i) top = top.max(joint.col(i));
  Eigen::ArrayXd sum = Eigen::ArrayXd::Zero(residual.size());
  for (int i = 0; i < m; ++i) {
    joint.col(i) = (joint.col(i) - top).exp();
    sum += joint.col(i);
  }
  const double log_likelihood = (top + sum.log()).sum();
  joint.colwise() *= sum.inverse();
  if (!std::isfinite(log_likelihood)) {
    throw NumericalError(
        "mixture log-likelihood is not finite: a residual is not finite or every mode has zero "
        "weight");
  }
  return log_likelihood;
}

Eigen::VectorXd mixture_log_densities(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                      const MixtureParameters& mixture) {
  Eigen::MatrixXd joint;
  log_joint(residual, mixture, joint);
  auto a = joint.array();
  Eigen::ArrayXd top = a.col(0);
  for (int i = 1; i < mixture.modes(); ++i) top = top.max(a.col(i));
  Eigen::ArrayXd sum = Eigen::ArrayXd::Zero(residual.size());
  for (int i = 0; i < mixture.modes(); ++i) sum += (a.col(i) - top).exp();
  Eigen::VectorXd out = (top + sum.log()).matrix();
  if (!out.allFinite()) {
    throw NumericalError(
        "mixture log-density is not finite: a residual is not finite or every mode has zero "
        "weight");
  }
  return out;
}

Eigen::VectorXd rounded_mixture_log_probabilities(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                                  const MixtureParameters& mixture,
                                                  double resolution) {
  require_positive(resolution, "the ranges' resolution");
  const Eigen::VectorXd density = mixture_log_densities(residual, mixture);
  Eigen::VectorXd out(residual.size());
  const double half = 0.5 * resolution;
  for (Eigen::Index k = 0; k < residual.size(); ++k) {
    double probability = 0.0;
    for (int i = 0; i < mixture.modes(); ++i) {
      const double sigma = std::sqrt(mixture.variance[i]);
      probability += mixture.weight[i] *
                     standard_normal_interval((residual[k] - half - mixture.mean[i]) / sigma,
                                              (residual[k] + half - mixture.mean[i]) / sigma);
    }
    // Beyond the reach of double precision in every mode's tail: the density times the
    // interval's width, which is what the probability tends to there.
    out[k] = probability > std::numeric_limits<double>::min() ? std::log(probability)
                                                               : density[k] + std::log(resolution);
  }
  return out;
}

double rounded_normal_log_probability(double residual, double mean, double variance,
                                      double resolution) {
  const double half = 0.5 * resolution;
  const double sigma = std::sqrt(variance);
  const double probability =
      standard_normal_interval((residual - half - mean) / sigma, (residual + half - mean) / sigma);
  if (probability > std::numeric_limits<double>::min()) return std::log(probability);
  const double z = (residual - mean) / sigma;
  return std::log(resolution / sigma) - 0.5 * std::log(2.0 * std::numbers::pi) - 0.5 * z * z;
}

double mixture_log_likelihood(const Eigen::Ref<const Eigen::VectorXd>& residual,
                              const MixtureParameters& mixture) {
  Eigen::MatrixXd scratch;
  return mixture_e_step(residual, mixture, scratch);
}

}  // namespace tofcomp::core
