// §3.3, Eq. 7: the junction temperature t^j from noisy case readings t^s, by a Kalman filter
// (causal, for real time) and a Rauch–Tung–Striebel smoother (a whole record). Both are linear in
// the readings, so each is an instance of Eq. 7's t̂^j = W t^s (plus the known inputs' part).
//
// Model: Eq. 3 driven by white noise, exact in discrete time for any step:
//   dx = (a x + b_power u + b_ambient t^a) dt + dβ,   E[dβ dβᵀ] = diag(q_c, q_j) dt
//   t^s_k = t^c(t_k) + μ_k,                           μ_k ~ N(0, r)             (Eq. 5)
// Over a step T with u and t^a held: x_{k+1} = Φ x_k + Γ [u, t^a] + w_k, w_k ~ N(0, Q_T), with
// Φ, Γ the zero-order hold of core/thermal_model.hpp and
//   Q_T = ∫_0^T e^{a s} diag(q_c, q_j) e^{aᵀ s} ds
// from Van Loan's block exponential (on T / 2^m with ‖a‖ T / 2^m ≤ 1/2, then doubled m times,
// Q_{2h} = Φ_h Q_h Φ_hᵀ + Q_h, so that long gaps neither overflow nor lose accuracy).
//
// Noise levels for the LMS 200 case sensor (0.0625 °C resolution, read at ~1 Hz):
//   r = 0.0625² / 12 ≈ 3.3e-4 K² (uniform quantization; add the sensor's own noise if known);
//   q_c = 1e-6 K²/s: with the 30 min case time constant a stationary case wander of ≈ 0.03 K
//   (room drafts, unmodelled heat);
//   q_j = 1e-4 K²/s: with the 12 s junction lag a stationary junction wander of ≈ 0.025 K
//   (errors of P and of the model).
// Quantization error is not white when the case drifts slowly (one level lasts ≈ 20 s at
// 0.003 K/s), so the reported standard deviations are optimistic at the level of q/√12.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/thermal_model.hpp"

namespace tofcomp::core {

struct ThermalNoise {
  double case_process_psd_k2_per_s = 1e-6;                  // q_c
  double junction_process_psd_k2_per_s = 1e-4;              // q_j
  double measurement_variance_k2 = 0.0625 * 0.0625 / 12.0;  // r
  // Throws InvalidInput unless q_c, q_j are finite and ≥ 0 and r is finite and > 0.
  void validate() const;
};

// A Gaussian belief over x = [t^c, t^j].
struct ThermalBelief {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
  // Throws InvalidInput unless finite, symmetric (to 1e-9 relative) and positive definite.
  void validate() const;
};

// A prior at a first case reading when the power's history before it is unknown: mean
// state_from_case_heat_flow(case_c, ambient_c); the case's standard deviation case_std_c, the
// junction's half the span its excess over the case can take, P R1 / 2 (between the laser off, 0,
// and on for long, P R1). A wider junction prior (a fixed 2 K before) let the smoother explain
// the first quantized case readings by a junction kelvins too hot, which then decayed over its
// first minute, and every lag of the junction (the model search's another thermal state)
// carried that start for as long as its time constant.
ThermalBelief prior_at_case_temperature(const ThermalParameters& parameters, double case_c,
                                        double ambient_c, double case_std_c);

// Q_T above: the covariance the process noise adds over a step of step_s ≥ 0 seconds.
Eigen::Matrix2d process_noise_covariance(const ThermalParameters& parameters,
                                         const ThermalNoise& noise, double step_s);

// The causal filter (Eq. 7 with a lower-triangular W), for real time. Variable step: each
// predict carries its own dt. Updates use the Joseph form and keep the covariance symmetric.
// Throws InvalidInput on a NaN or Inf argument, a negative dt, or an on fraction outside [0, 1];
// the state is unchanged by a call that throws.
class ThermalKalmanFilter {
 public:
  ThermalKalmanFilter(const ThermalParameters& parameters, const ThermalNoise& noise,
                      const ThermalBelief& initial);

  // Time update over dt_s ≥ 0 with the on fraction and ambient held over the interval.
  void predict(double dt_s, double power_on_fraction, double ambient_c);
  // Measurement update with a case reading t^s (°C).
  void update(double case_measurement_c);

  const ThermalBelief& belief() const { return belief_; }
  double case_mean_c() const { return belief_.mean[0]; }
  double junction_mean_c() const { return belief_.mean[1]; }
  double junction_std_c() const;
  // Σ log N(innovation; 0, innovation variance) over the updates so far: the likelihood of the
  // readings, for choosing noise levels.
  double log_likelihood() const { return log_likelihood_; }

 private:
  ThermalParameters parameters_;
  ThermalNoise noise_;
  ThermalBelief belief_;
  DiscreteThermalModel model_;  // the last step's hold, reused while dt repeats
  Eigen::Matrix2d process_covariance_;
  double log_likelihood_ = 0.0;
};

// The smoothed record: t^c, t^j and their standard deviations at every requested instant.
struct SmoothedThermalRecord {
  Eigen::VectorXd case_mean_c;
  Eigen::VectorXd case_std_c;
  Eigen::VectorXd junction_mean_c;
  Eigen::VectorXd junction_std_c;
  double log_likelihood = 0.0;  // of the readings, as ThermalKalmanFilter::log_likelihood
};

// Rauch–Tung–Striebel smoothing of a whole record (Eq. 7 with a full W). `initial` is the belief
// at times_s[0] before its reading. The on fraction and ambient at times_s[k] are held until
// times_s[k+1]; case_measurement_c[k] is used only where measured[k] is true (other entries may
// be anything, NaN included), so a mixed-rate log (ranges at 75 Hz, temperatures at 1 Hz) gets
// the junction temperature at every range instant. Memory O(K).
SmoothedThermalRecord smooth_thermal_record(
    const ThermalParameters& parameters, const ThermalNoise& noise, const ThermalBelief& initial,
    const Eigen::Ref<const Eigen::VectorXd>& times_s,
    const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
    const Eigen::Ref<const Eigen::VectorXd>& ambient_c,
    const Eigen::Ref<const Eigen::VectorXd>& case_measurement_c, const std::vector<bool>& measured);

}  // namespace tofcomp::core
