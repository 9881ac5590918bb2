// Eq. 8, trained: y_k = d + H(t^j_k) θ + w_k, with w_k drawn from the lasing-mode mixture.
// This is what training produces, what testing and the daemon consume, and what a calibration
// file stores.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/basis.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

// The junction temperatures a model was trained on.
struct TemperatureRange {
  double min_c = 0.0;
  double max_c = 0.0;
  bool contains(double t_c) const { return t_c >= min_c && t_c <= max_c; }
  double clamp(double t_c) const;
};

struct MeasurementModel {
  Basis basis;
  Eigen::VectorXd theta;      // θ of Eq. 8, one coefficient per basis column
  MixtureParameters mixture;  // μ_i, σ_i², π_i of the lasing modes
  // Where H(t) θ was fitted. Beyond it the bias continues along its tangent at the nearer end
  // (first order, as chrony bounds its temperature compensation to the fitted range) rather than
  // along the basis: a polynomial fitted over a few kelvin says nothing of its higher terms a few
  // kelvin further, while the trend at the edge holds best nearby. Absent: no bound (a
  // calibration file written before the range was stored).
  std::optional<TemperatureRange> trained_junction_c;

  // Throws InvalidInput when θ does not match the basis or the mixture is invalid.
  void validate() const;
  // Whether H(t) θ at t_c is extrapolated (t_c outside trained_junction_c).
  bool extrapolates(double junction_temperature_c) const;
  // The temperature-induced bias H(t) θ at each junction temperature (K-vector), continued along
  // its tangent beyond trained_junction_c.
  Eigen::VectorXd bias(const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c) const;
  // H(t) θ at one temperature, for the real-time path (continued as bias()).
  double bias_at(double junction_temperature_c) const;

 private:
  // H(t) θ of the basis itself, at any t.
  double basis_bias_at(double junction_temperature_c) const;
};

}  // namespace tofcomp::core
