// Seeded draws from the paper's measurement model (Eq. 8), for tests: the truth is known by
// construction, so estimates can be checked against it.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "core/gaussian_mixture.hpp"

namespace tofcomp::testing {

// The distance the synthetic ranges are drawn at (mm), and a smooth negative bias of a few mm
// over the paper's junction range (24.8-28.8 °C), the shape of its Fig. 4: a cubic.
inline constexpr double kSyntheticDistanceMm = 3000.0;
inline double cubic_bias(double t) {
  const double x = t - 26.8;
  return -4.0 * x + 0.8 * x * x + 0.35 * x * x * x;
}

// The normal density N(x; mean, variance), written out here as the tests' own reference for the
// mixture's component densities (Eq. 9).
inline double normal_pdf(double x, double mean, double variance) {
  return std::exp(-0.5 * (x - mean) * (x - mean) / variance) /
         std::sqrt(2.0 * std::numbers::pi * variance);
}

struct SyntheticMeasurements {
  Eigen::VectorXd junction_temperature_c;
  Eigen::VectorXd range;      // y_k
  Eigen::VectorXd true_bias;  // the bias function at t_k
  Eigen::VectorXi mode;       // the lasing mode that produced y_k (0-based)
};

// A junction temperature that heats from lo to hi and cools back, over `cycles` cycles,
// like the paper's power cycling (24.8–28.8 °C in §8).
inline Eigen::VectorXd cycling_temperature(Eigen::Index samples, double lo = 24.8, double hi = 28.8,
                                           double cycles = 2.0) {
  Eigen::VectorXd t(samples);
  for (Eigen::Index k = 0; k < samples; ++k) {
    const double phase =
        2.0 * std::numbers::pi * cycles * static_cast<double>(k) / static_cast<double>(samples);
    t[k] = lo + (hi - lo) * 0.5 * (1.0 - std::cos(phase));
  }
  return t;
}

// y_k = d + bias(t_k) + w_k, w_k from mode i with probability weight[i] (Eq. 8).
inline SyntheticMeasurements draw_measurements(const Eigen::VectorXd& temperature_c,
                                               double distance,
                                               const std::function<double(double)>& bias,
                                               const core::MixtureParameters& noise,
                                               unsigned seed) {
  std::mt19937_64 rng(seed);
  std::discrete_distribution<int> pick(noise.weight.data(),
                                       noise.weight.data() + noise.weight.size());
  std::normal_distribution<double> standard(0.0, 1.0);
  SyntheticMeasurements out;
  const Eigen::Index k = temperature_c.size();
  out.junction_temperature_c = temperature_c;
  out.range.resize(k);
  out.true_bias.resize(k);
  out.mode.resize(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    const int m = pick(rng);
    out.mode[i] = m;
    out.true_bias[i] = bias(temperature_c[i]);
    out.range[i] =
        distance + out.true_bias[i] + noise.mean[m] + std::sqrt(noise.variance[m]) * standard(rng);
  }
  return out;
}

inline core::MixtureParameters mixture(std::initializer_list<double> mean,
                                       std::initializer_list<double> stddev,
                                       std::initializer_list<double> weight) {
  core::MixtureParameters m;
  m.mean = Eigen::Map<const Eigen::VectorXd>(mean.begin(), static_cast<Eigen::Index>(mean.size()));
  m.variance =
      Eigen::Map<const Eigen::VectorXd>(stddev.begin(), static_cast<Eigen::Index>(stddev.size()))
          .array()
          .square()
          .matrix();
  m.weight =
      Eigen::Map<const Eigen::VectorXd>(weight.begin(), static_cast<Eigen::Index>(weight.size()));
  return m;
}

}  // namespace tofcomp::testing
