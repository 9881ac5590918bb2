#include "core/gaussian_mixture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/validation.hpp"
#include "core/vector_math.hpp"

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

// P(a_k ≤ Z < b_k) for a standard normal Z, element-wise, from the tails on the side of each
// interval, so that an interval far out in a tail keeps its relative accuracy: with
// Q(z) = ½ erfc(z/√2), Q(a) − Q(b) when a ≥ 0, Q(−b) − Q(−a) when b ≤ 0, else 1 − Q(b) − Q(−a).
Eigen::ArrayXd standard_normal_intervals(const Eigen::ArrayXd& a, const Eigen::ArrayXd& b) {
  const Eigen::Index n = a.size();
  Eigen::ArrayXd first(n), second(n);  // the two tails' arguments, then their erfc
  for (Eigen::Index k = 0; k < n; ++k) {
    if (a[k] >= 0.0) {
      first[k] = a[k];
      second[k] = b[k];
    } else if (b[k] <= 0.0) {
      first[k] = -b[k];
      second[k] = -a[k];
    } else {
      first[k] = b[k];
      second[k] = -a[k];
    }
  }
  first /= std::numbers::sqrt2;
  second /= std::numbers::sqrt2;
  erfc_in_place(first);
  erfc_in_place(second);
  Eigen::ArrayXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double q_first = 0.5 * first[k], q_second = 0.5 * second[k];
    out[k] = a[k] >= 0.0 || b[k] <= 0.0 ? q_first - q_second : 1.0 - q_first - q_second;
  }
  return out;
}

}  // namespace

MixtureParameters without_mode(const MixtureParameters& mixture, int mode) {
  mixture.validate();
  if (mode < 0 || mode >= mixture.modes()) {
    throw InvalidInput("mixture: no mode " + std::to_string(mode + 1) + " of " +
                       std::to_string(mixture.modes()) + " to drop");
  }
  const double rest = 1.0 - mixture.weight[mode];
  if (mixture.modes() < 2 || !(rest > 0.0)) {
    throw InvalidInput("mixture: dropping mode " + std::to_string(mode + 1) +
                       " would leave no mode with weight");
  }
  const int m = mixture.modes() - 1;
  MixtureParameters out{Eigen::VectorXd(m), Eigen::VectorXd(m), Eigen::VectorXd(m)};
  for (int i = 0, j = 0; i < mixture.modes(); ++i) {
    if (i == mode) continue;
    out.mean[j] = mixture.mean[i];
    out.variance[j] = mixture.variance[i];
    out.weight[j] = mixture.weight[i] / rest;
    ++j;
  }
  return out;
}

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
    joint.col(i) -= top;
    exp_in_place(joint.col(i));
    sum += joint.col(i);
  }
  Eigen::ArrayXd log_sum = sum;
  log_in_place(log_sum);
  const double log_likelihood = (top + log_sum).sum();
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
  for (int i = 0; i < mixture.modes(); ++i) {
    a.col(i) -= top;
    exp_in_place(a.col(i));
    sum += a.col(i);
  }
  log_in_place(sum);
  Eigen::VectorXd out = (top + sum).matrix();
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
  const double half = 0.5 * resolution;
  const auto e = residual.array();
  Eigen::ArrayXd probability = Eigen::ArrayXd::Zero(residual.size());
  for (int i = 0; i < mixture.modes(); ++i) {
    const double sigma = std::sqrt(mixture.variance[i]);
    probability += mixture.weight[i] * standard_normal_intervals((e - half - mixture.mean[i]) / sigma,
                                                                 (e + half - mixture.mean[i]) / sigma);
  }
  Eigen::ArrayXd out = probability;
  log_in_place(out);
  // Beyond the reach of double precision in every mode's tail: the density times the
  // interval's width, which is what the probability tends to there.
  if ((probability <= std::numeric_limits<double>::min()).any()) {
    const Eigen::VectorXd density = mixture_log_densities(residual, mixture);
    for (Eigen::Index k = 0; k < out.size(); ++k) {
      if (!(probability[k] > std::numeric_limits<double>::min())) {
        out[k] = density[k] + std::log(resolution);
      }
    }
  }
  return out.matrix();
}

Eigen::ArrayXd rounded_normal_log_probabilities(const Eigen::Ref<const Eigen::ArrayXd>& residual,
                                                const Eigen::Ref<const Eigen::ArrayXd>& mean,
                                                const Eigen::Ref<const Eigen::ArrayXd>& variance,
                                                double resolution) {
  const double half = 0.5 * resolution;
  const Eigen::ArrayXd sigma = variance.sqrt();
  const Eigen::ArrayXd probability =
      standard_normal_intervals((residual - half - mean) / sigma, (residual + half - mean) / sigma);
  Eigen::ArrayXd out = probability;
  log_in_place(out);
  for (Eigen::Index k = 0; k < out.size(); ++k) {
    if (probability[k] > std::numeric_limits<double>::min()) continue;
    const double z = (residual[k] - mean[k]) / sigma[k];
    out[k] = std::log(resolution / sigma[k]) - 0.5 * std::log(2.0 * std::numbers::pi) - 0.5 * z * z;
  }
  return out;
}

double mixture_log_likelihood(const Eigen::Ref<const Eigen::VectorXd>& residual,
                              const MixtureParameters& mixture) {
  Eigen::MatrixXd scratch;
  return mixture_e_step(residual, mixture, scratch);
}

MixtureParameters modes_before_rounding(MixtureParameters fitted, double resolution) {
  const double rounding = resolution * resolution / 12.0;
  for (Eigen::Index i = 0; i < fitted.variance.size(); ++i) {
    fitted.variance[i] =
        std::max(fitted.variance[i] - rounding, kSheppardKeptShare * fitted.variance[i]);
  }
  return fitted;
}

}  // namespace tofcomp::core
