#include "core/kalman.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <unsupported/Eigen/MatrixFunctions>
#include <utility>

#include "core/error.hpp"
#include "core/step_cache.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

// The smoother solves with the predicted covariance by Cholesky only when its reciprocal
// condition number is above this (a covariance this near singular takes the pseudo-inverse).
constexpr double kSmootherReciprocalCondition = 1e-12;

// λ_min / λ_max of a symmetric 2 × 2 matrix, in closed form (Eigen's LLT::rcond estimates the
// 1-norm's by iteration, which cost the smoother as much as its own arithmetic): λ_max =
// mean + √(half-difference² + b²), λ_min = det / λ_max, free of the cancellation of mean − √….
// 0 when the matrix is not positive definite.
double reciprocal_condition(const Eigen::Matrix2d& m) {
  const double largest = 0.5 * (m(0, 0) + m(1, 1)) + std::hypot(0.5 * (m(0, 0) - m(1, 1)), m(0, 1));
  if (!(largest > 0.0)) return 0.0;
  const double smallest = (m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0)) / largest;
  return std::max(smallest / largest, 0.0);
}

void symmetrize(Eigen::Matrix2d& m) {
  const double off = 0.5 * (m(0, 1) + m(1, 0));
  m(0, 1) = off;
  m(1, 0) = off;
}

void require_step(double dt_s) {
  require_finite(dt_s, "time step dt_s");
  if (dt_s < 0.0) {
    std::ostringstream msg;
    msg << "time step dt_s is " << dt_s << " s: time cannot run backwards";
    throw InvalidInput(msg.str());
  }
}

// The hold and process noise of one step.
struct StepModel {
  DiscreteThermalModel hold{Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(),
                            Eigen::Vector2d::Zero(), -1.0};  // no step yet
  Eigen::Matrix2d process_covariance = Eigen::Matrix2d::Zero();
};

StepModel step_model(const ThermalParameters& parameters, const ThermalNoise& noise, double dt_s) {
  return {discretize_zoh(parameters, dt_s), process_noise_covariance(parameters, noise, dt_s)};
}

void refresh(StepModel& step, const ThermalParameters& parameters, const ThermalNoise& noise,
             double dt_s) {
  if (dt_s == step.hold.step_s) return;
  step = step_model(parameters, noise, dt_s);
}

// Kalman time update through Eq. 5.
ThermalBelief predicted(const ThermalBelief& belief, const StepModel& step,
                        double power_on_fraction, double ambient_c) {
  const DiscreteThermalModel& m = step.hold;
  ThermalBelief out;
  out.mean = m.a * belief.mean + m.b_power * power_on_fraction + m.b_ambient * ambient_c;
  out.covariance = m.a * belief.covariance * m.a.transpose() + step.process_covariance;
  symmetrize(out.covariance);
  return out;
}

// Kalman measurement update with C = [1, 0] (Eq. 5), Joseph form. Returns the reading's
// log-likelihood log N(innovation; 0, s).
double updated(ThermalBelief& belief, double case_measurement_c, double measurement_variance) {
  const double innovation = case_measurement_c - belief.mean[0];
  const double innovation_variance = belief.covariance(0, 0) + measurement_variance;
  const Eigen::Vector2d gain = belief.covariance.col(0) / innovation_variance;
  belief.mean += gain * innovation;
  Eigen::Matrix2d i_minus_kc = Eigen::Matrix2d::Identity();
  i_minus_kc.col(0) -= gain;
  belief.covariance = i_minus_kc * belief.covariance * i_minus_kc.transpose() +
                      measurement_variance * gain * gain.transpose();
  symmetrize(belief.covariance);
  return -0.5 * (std::log(2.0 * std::numbers::pi * innovation_variance) +
                 innovation * innovation / innovation_variance);
}

double standard_deviation(double variance) {
  return std::sqrt(std::max(variance, 0.0));
}

}  // namespace

void ThermalNoise::validate() const {
  for (const auto& [value, name] :
       {std::pair{case_process_psd_k2_per_s, "case process noise density (K²/s)"},
        std::pair{junction_process_psd_k2_per_s, "junction process noise density (K²/s)"}}) {
    require_finite(value, name);
    if (value < 0.0) {
      std::ostringstream msg;
      msg << name << " is " << value << ": it must not be negative";
      throw InvalidInput(msg.str());
    }
  }
  require_positive(measurement_variance_k2, "case sensor measurement variance (K²)");
}

void ThermalBelief::validate() const {
  require_finite(mean, "belief mean");
  require_finite(covariance, "belief covariance");
  const double scale = covariance.cwiseAbs().maxCoeff();
  if (std::abs(covariance(0, 1) - covariance(1, 0)) > 1e-9 * scale) {
    throw InvalidInput("belief covariance is not symmetric");
  }
  if (!(covariance(0, 0) > 0.0) || !(covariance.determinant() > 0.0)) {
    throw InvalidInput("belief covariance is not positive definite");
  }
}

ThermalBelief prior_at_case_temperature(const ThermalParameters& parameters, double case_c,
                                        double ambient_c, double case_std_c) {
  require_positive(case_std_c, "prior case standard deviation");
  ThermalBelief b;
  b.mean = state_from_case_heat_flow(parameters, case_c, ambient_c);
  const double junction_std_c = 0.5 * parameters.power_w * parameters.r1_k_per_w;
  b.covariance =
      Eigen::Vector2d(case_std_c * case_std_c, junction_std_c * junction_std_c).asDiagonal();
  return b;
}

// Van Loan (1978): exp([[−a, Q_c], [0, aᵀ]] h) = [[·, G12], [0, G22]], Φ_h = G22ᵀ,
// Q_h = Φ_h G12; then Q_{2h} = Φ_h Q_h Φ_hᵀ + Q_h up to the full step.
Eigen::Matrix2d process_noise_covariance(const ThermalParameters& parameters,
                                         const ThermalNoise& noise, double step_s) {
  noise.validate();
  require_step(step_s);
  const Eigen::Matrix2d a = continuous_model(parameters).a;
  const Eigen::Matrix2d density =
      Eigen::Vector2d(noise.case_process_psd_k2_per_s, noise.junction_process_psd_k2_per_s)
          .asDiagonal();
  const double norm = a.cwiseAbs().rowwise().sum().maxCoeff();
  double h = step_s;
  int doublings = 0;
  while (norm * h > 0.5) {
    h *= 0.5;
    ++doublings;
  }
  Eigen::Matrix4d block = Eigen::Matrix4d::Zero();
  block.topLeftCorner<2, 2>() = -a * h;
  block.topRightCorner<2, 2>() = density * h;
  block.bottomRightCorner<2, 2>() = a.transpose() * h;
  const Eigen::Matrix4d e = block.exp();
  Eigen::Matrix2d phi = e.bottomRightCorner<2, 2>().transpose();
  Eigen::Matrix2d q = phi * e.topRightCorner<2, 2>();
  symmetrize(q);
  for (int i = 0; i < doublings; ++i) {
    q = phi * q * phi.transpose() + q;
    symmetrize(q);
    phi = phi * phi;
  }
  return q;
}

ThermalKalmanFilter::ThermalKalmanFilter(const ThermalParameters& parameters,
                                         const ThermalNoise& noise, const ThermalBelief& initial)
    : parameters_(parameters), noise_(noise), belief_(initial) {
  parameters_.validate();
  noise_.validate();
  belief_.validate();
  model_ = discretize_zoh(parameters_, 0.0);
  process_covariance_.setZero();
}

// Eq. 5's time update over a variable step.
void ThermalKalmanFilter::predict(double dt_s, double power_on_fraction, double ambient_c) {
  require_step(dt_s);
  require_on_fraction(power_on_fraction, "power on fraction");
  require_finite(ambient_c, "ambient temperature");
  StepModel step{model_, process_covariance_};
  refresh(step, parameters_, noise_, dt_s);
  belief_ = predicted(belief_, step, power_on_fraction, ambient_c);
  model_ = step.hold;
  process_covariance_ = step.process_covariance;
}

// Eq. 5's measurement update.
void ThermalKalmanFilter::update(double case_measurement_c) {
  require_finite(case_measurement_c, "case temperature reading");
  log_likelihood_ += updated(belief_, case_measurement_c, noise_.measurement_variance_k2);
}

double ThermalKalmanFilter::junction_std_c() const {
  return standard_deviation(belief_.covariance(1, 1));
}

// Eq. 7 with a full W: forward Kalman filter, then the Rauch–Tung–Striebel backward pass
//   G_k = P_{k|k} Φ_kᵀ P_{k+1|k}⁻¹,
//   m_{k|K} = m_{k|k} + G_k (m_{k+1|K} − m_{k+1|k}),
//   P_{k|K} = P_{k|k} + G_k (P_{k+1|K} − P_{k+1|k}) G_kᵀ.
// Only the filtered beliefs are stored; the predictions are recomputed backwards.
SmoothedThermalRecord smooth_thermal_record(
    const ThermalParameters& parameters, const ThermalNoise& noise, const ThermalBelief& initial,
    const Eigen::Ref<const Eigen::VectorXd>& times_s,
    const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
    const Eigen::Ref<const Eigen::VectorXd>& ambient_c,
    const Eigen::Ref<const Eigen::VectorXd>& case_measurement_c,
    const std::vector<bool>& measured) {
  parameters.validate();
  noise.validate();
  initial.validate();
  require_thermal_inputs(power_on_fraction, ambient_c);
  require_same_length(times_s.size(), "sample times", power_on_fraction.size(),
                      "power on fractions");
  require_same_length(case_measurement_c.size(), "case readings", times_s.size(), "sample times");
  require_same_length(static_cast<Eigen::Index>(measured.size()), "measurement mask",
                      times_s.size(), "sample times");
  require_sample_times(times_s);
  const Eigen::Index k = times_s.size();
  for (Eigen::Index i = 0; i < k; ++i) {
    if (measured[static_cast<std::size_t>(i)]) {
      require_finite(case_measurement_c[i], "case reading at a measured instant");
    }
  }

  SmoothedThermalRecord out;
  std::vector<ThermalBelief> filtered(static_cast<std::size_t>(k));
  StepCache<StepModel> steps;
  const auto step_at = [&](Eigen::Index i) -> const StepModel& {
    return steps.at(times_s[i] - times_s[i - 1], [&](double dt_s) {
      return step_model(parameters, noise, dt_s);
    });
  };
  ThermalBelief belief = initial;
  for (Eigen::Index i = 0; i < k; ++i) {
    if (i > 0) {
      belief = predicted(belief, step_at(i), power_on_fraction[i - 1], ambient_c[i - 1]);
    }
    if (measured[static_cast<std::size_t>(i)]) {
      out.log_likelihood += updated(belief, case_measurement_c[i], noise.measurement_variance_k2);
    }
    filtered[static_cast<std::size_t>(i)] = belief;
  }

  out.case_mean_c.resize(k);
  out.case_std_c.resize(k);
  out.junction_mean_c.resize(k);
  out.junction_std_c.resize(k);
  ThermalBelief smoothed = filtered.back();
  for (Eigen::Index i = k - 1;; --i) {
    out.case_mean_c[i] = smoothed.mean[0];
    out.junction_mean_c[i] = smoothed.mean[1];
    out.case_std_c[i] = standard_deviation(smoothed.covariance(0, 0));
    out.junction_std_c[i] = standard_deviation(smoothed.covariance(1, 1));
    if (i == 0) break;
    const ThermalBelief& f = filtered[static_cast<std::size_t>(i - 1)];
    const StepModel& step = step_at(i);
    const ThermalBelief p = predicted(f, step, power_on_fraction[i - 1], ambient_c[i - 1]);
    // G = P_f Φᵀ P_p⁻¹, solved as Gᵀ = P_p⁻¹ Φ P_f: by Cholesky where P_p is well conditioned
    // (a fifth of the smoother's time went to a 2 × 2 pivoted QR), else by the pseudo-inverse,
    // which keeps a singular P_p (no process noise and a collapsed covariance) finite.
    const Eigen::Matrix2d right = step.hold.a * f.covariance;
    const Eigen::Matrix2d gain =
        (reciprocal_condition(p.covariance) > kSmootherReciprocalCondition
             ? Eigen::Matrix2d(Eigen::LLT<Eigen::Matrix2d>(p.covariance).solve(right))
             : Eigen::Matrix2d(p.covariance.completeOrthogonalDecomposition().solve(right)))
            .transpose();
    smoothed.mean = f.mean + gain * (smoothed.mean - p.mean);
    smoothed.covariance =
        f.covariance + gain * (smoothed.covariance - p.covariance) * gain.transpose();
    symmetrize(smoothed.covariance);
    if (!smoothed.mean.allFinite() || !smoothed.covariance.allFinite()) {
      throw NumericalError("the RTS smoother produced a non-finite estimate");
    }
  }
  return out;
}

}  // namespace tofcomp::core
