// Eq. 8, trained: y_k = d + H(t^j_k) θ + w_k, with w_k drawn from the lasing-mode mixture.
// This is what training produces, what testing and the daemon consume, and what a calibration
// file stores.
#pragma once

#include <Eigen/Core>

#include "core/basis.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

struct MeasurementModel {
  Basis basis;
  Eigen::VectorXd theta;    // θ of Eq. 8, one coefficient per basis column
  MixtureParameters noise;  // μ_i, σ_i², π_i of the modes

  // Throws InvalidInput when θ does not match the basis or the mixture is invalid.
  void validate() const;
  // The temperature-induced bias H(t) θ at each junction temperature (K-vector).
  Eigen::VectorXd bias(const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c) const;
  // H(t) θ at one temperature, for the real-time path.
  double bias_at(double junction_temperature_c) const;
};

}  // namespace tofcomp::core
