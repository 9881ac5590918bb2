// §3.1: the thermal network of a pulsed ToF LiDAR (Fig. 5, Eq. 3) and its discretizations
// (Eq. 4-6).
//
// State x = [t^c, t^j] in °C: t^c the case temperature a sensor reads (t^s = t^c + noise, Eq. 5),
// t^j the laser junction. Inputs: u ∈ [0, 1], the laser's on fraction over a step (the heat is
// u·P), and the ambient t^a. Eq. 3 as printed:
//   ṫ^c = t^j / (R1 C2) − t^c (1/(R2 C2) + 1/(R1 C2)) + t^a / (R2 C2)
//   ṫ^j = u P / C1 + t^c / (R1 C1) − t^j / (R1 C1)
// The heat u·P enters the junction node (capacity C1), crosses R1 to the case node (capacity
// C2), which loses it through R2 to the ambient.
//
// A discrete model is x_{k+1} = a x_k + b_power u_k + b_ambient t^a_k, the inputs held over the
// step. Eq. 6 is forward Euler: it needs T well below the fast time constant (≈ R1 C1) and is
// kept to reproduce the paper. The zero-order hold is exact for any T and is what the
// identification (core/thermal_identification.hpp) and the Kalman filter (core/kalman.hpp) use.
//
// Ambient increments: the v̄_k = t^a_k − t^a_{k−1} of Eq. 4.
// Both discretizations keep the rest state of Eq. 3: with u = 0 the state x = 1·t^a (1 = [1, 1])
// is a fixed point, so a·1 + b_ambient = 1 (for Eq. 6 it is direct algebra on A and B′: the rows
// of [A B′] sum to one). In coordinates relative to the ambient, x̃_k = x_k − 1·t^a_k,
//   x̃_{k+1} = a x̃_k + b_power u_k + (a·1 + b_ambient − 1) t^a_k − 1 (t^a_{k+1} − t^a_k)
//           = a x̃_k + b_power u_k − 1 v̄_{k+1}.
// A constant ambient drops out, and only its increments drive the relative state, entering both
// states with gain −1 one step ahead. The paper's B′ v̄_k in Eq. 5 puts the ambient gain of the
// case equation in place of −1 and treats v̄ as process noise; tofcomp feeds the measured t^a
// itself, which is exact, and leaves unmodelled ambient drift to the case process noise of
// core/kalman.hpp.
#pragma once

#include <Eigen/Core>
#include <string_view>

namespace tofcomp::core {

struct ThermalParameters {
  double r1_k_per_w = 0.0;  // R1: junction (transmitter) to case
  double r2_k_per_w = 0.0;  // R2: case to ambient
  double c1_j_per_k = 0.0;  // C1: capacity of the junction node
  double c2_j_per_k = 0.0;  // C2: capacity of the case node
  double power_w = 0.0;     // P: heat generated while the laser is on
  // Throws InvalidInput naming the first field that is not a positive finite number.
  void validate() const;
};

// An example resembling the paper's SICK LMS 200 (§8.1), used by the tests:
//   P = 10 W (20 W electrical × 0.5, Algorithm 1 step 3);
//   R2 = 0.48 K/W and R1 = 0.2 K/W put the case 4.8 K and the junction 6.8 K above a 22 °C room
//   at rest with the laser on (junction 28.8 °C, the top of the paper's 24.8–28.8 °C);
//   C2 = 3750 J/K (≈ 4.5 kg of mostly aluminium) gives the case a ≈ 30 min time constant, and
//   C1 = 60 J/K a 12 s junction lag.
ThermalParameters lms200_example_parameters();

// Eq. 3 as ẋ = a x + b_power u + b_ambient t^a, with b_power = [0, P/C1] already carrying P.
struct ContinuousThermalModel {
  Eigen::Matrix2d a;
  Eigen::Vector2d b_power;
  Eigen::Vector2d b_ambient;
};

// x_{k+1} = a x_k + b_power u_k + b_ambient t^a_k over a step of step_s seconds; u_k is the on
// fraction (0 or 1 for the paper's ū_k / P), b_power already carries P.
struct DiscreteThermalModel {
  Eigen::Matrix2d a;
  Eigen::Vector2d b_power;
  Eigen::Vector2d b_ambient;
  double step_s = 0.0;
};

// A simulated record: case and junction temperatures in °C, one entry per sample.
struct ThermalTrajectory {
  Eigen::VectorXd case_c;
  Eigen::VectorXd junction_c;
};

// Eq. 3: the continuous-time matrices.
ContinuousThermalModel continuous_model(const ThermalParameters& parameters);

// Eq. 6 as printed (forward Euler): A, B·P and B′ for a step T > 0. Throws InvalidInput when T
// makes the Euler recursion unstable (an eigenvalue of A on or outside the unit circle): use
// discretize_zoh then.
DiscreteThermalModel discretize_euler(const ThermalParameters& parameters, double step_s);

// Exact discretization of Eq. 3 with the inputs held over the step (zero-order hold): the
// matrix exponential of the augmented matrix [[a, b_power, b_ambient], [0, 0, 0]]·T. Any T ≥ 0
// (T = 0 gives the identity, for repeated timestamps).
DiscreteThermalModel discretize_zoh(const ThermalParameters& parameters, double step_s);

// Eq. 3's second line, the junction's heating rate in °C/s at the state [t^c, t^j] with the
// laser's on fraction u: ṫ^j = u P / C1 + (t^c − t^j) / (R1 C1). The ambient does not enter it.
// The grammar's heating-rate covariate (offline at the smoothed state, calibration/
// junction_estimate.hpp) and the daemon's (at the filter's predicted state) are this one rate.
// `parameters` are taken as valid (ThermalParameters::validate).
double junction_rate_c_per_s(const ThermalParameters& parameters, double case_c, double junction_c,
                             double power_on_fraction);
// The heating rate is a covariate in °C/min.
inline constexpr double kSecondsPerMinute = 60.0;

// Eq. 3 at rest for constant inputs: t^c = t^a + u P R2, t^j = t^c + u P R1.
Eigen::Vector2d equilibrium_state(const ThermalParameters& parameters, double power_on_fraction,
                                  double ambient_c);

// The case at a measured temperature and the junction at rest relative to it (its fast node
// settled, Eq. 3's second line with ṫ^j = 0): [t^c, t^c + u P R1]. The starting state of the
// prediction-error method and the mean of the Kalman prior.
Eigen::Vector2d state_at_case_temperature(const ThermalParameters& parameters, double case_c,
                                          double power_on_fraction);

// The state a case reading implies when the power's history is unknown (the start of a record):
// the junction settled (Eq. 3's second line with ṫ^j = 0) on the heat the case sheds to the
// ambient, (t^c − t^a) / R2 (its first line with ṫ^c = 0), bounded by the power between 0 and P:
// [t^c, t^c + R1 · clamp((t^c − t^a) / R2, 0, P)]. A record that starts as the laser is switched
// on from cold has its junction at the case, not P R1 above it (state_at_case_temperature's
// junction settled to a power that has only just come on); one that starts after hours at the
// power's steady state gives the same as state_at_case_temperature.
Eigen::Vector2d state_from_case_heat_flow(const ThermalParameters& parameters, double case_c,
                                          double ambient_c);

// Eq. 5 without noise: x_0 = initial_state, x_{k+1} = a x_k + b_power u_k + b_ambient t^a_k.
// Returns x_0 .. x_{K−1} for inputs of length K ≥ 1 (the last inputs are not used).
ThermalTrajectory simulate(const DiscreteThermalModel& model, const Eigen::Vector2d& initial_state,
                           const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
                           const Eigen::Ref<const Eigen::VectorXd>& ambient_c);

// The same on irregular sample times (non-decreasing, seconds): the inputs at times[k] are held
// over [times[k], times[k+1]) and each interval is discretized exactly (zero-order hold).
// Returns the state at every time, x(times[0]) = initial_state.
ThermalTrajectory simulate_at_times(const ThermalParameters& parameters,
                                    const Eigen::Vector2d& initial_state,
                                    const Eigen::Ref<const Eigen::VectorXd>& times_s,
                                    const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
                                    const Eigen::Ref<const Eigen::VectorXd>& ambient_c);

// Input checks shared by the thermal algorithms; each throws InvalidInput naming the offence.
// On fractions and ambients: one length ≥ 1, finite, every on fraction in [0, 1].
void require_thermal_inputs(const Eigen::Ref<const Eigen::VectorXd>& power_on_fraction,
                            const Eigen::Ref<const Eigen::VectorXd>& ambient_c);
// Sample times: finite and non-decreasing.
void require_sample_times(const Eigen::Ref<const Eigen::VectorXd>& times_s);
// One on fraction in [0, 1].
void require_on_fraction(double power_on_fraction, std::string_view name);

}  // namespace tofcomp::core
