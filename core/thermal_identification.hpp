// §3.2: identifying the thermal model of Eq. 3/5 — Algorithm 1 (datasheet and one equilibrium
// measurement), a prediction-error method on logged case temperatures, and the goodness-of-fit
// measures of §8.1 (Eq. 26) and the usual NRMSE fit.
//
// Prediction-error method. The predictor is the output-error one: the case temperature
// simulated from the inputs alone by the exact zero-order hold of Eq. 3 on the log's own time
// stamps (Ljung's output-error model; no Kalman gain, so the fit is the model's simulation
// quality, as in §8.1). Initial state: the case at the first logged reading and the junction at
// rest relative to it (state_at_case_temperature), so the first residual is zero and no initial
// state is estimated; start a log after the device has been idle or running steadily for a
// while for this to hold. Levenberg–Marquardt on the logarithms of the free parameters (which
// keeps them positive and makes their sensitivities relative), with the exact Jacobian from the
// sensitivity equations (block matrix exponential for ∂Φ/∂p), a bounded log step per iteration
// and a bounded number of iterations.
//
// Identifiability from the case temperature alone (derived from Eq. 3 by Laplace transform):
//   T^c(s) = [P R2 U(s) + (R1 C1 s + 1) T^a(s)] / (R1 R2 C1 C2 s² + (R2 C2 + (R1 + R2) C1) s + 1).
// (1) Heat scale: (P, R1, R2, C1, C2) → (sP, R1/s, R2/s, sC1, sC2) leaves both t^c and t^j
//     unchanged, so the five parameters are never identifiable together, whatever the data; the
//     temperatures depend on P R1, P R2, R1 C1 and R2 C2 only.
// (2) With a constant ambient (the paper's controlled room) the case reveals three numbers:
//     the gain P R2 and the two denominator coefficients. At most three parameters can be free.
//     Of the ten triples only {R1, C1, C2} is structurally unidentifiable (with P R2 fixed, the
//     three enter only the two coefficients); the others are identifiable for generic values
//     (e.g. {R2, C1, C2} unless (R1 + R2) C1 = R2 C2). Pairs and singles are identifiable.
//     The default frees {R2, C1, C2} with R1 and P from the datasheet (Algorithm 1), which is
//     what the junction estimate then rests on: its offset above the case at rest is u P R1.
// (3) A varying ambient adds the zero R1 C1 s + 1, so P R1, P R2, R1 C1 and R2 C2 are all
//     revealed and any four parameters (the fifth fixes the heat scale) become identifiable in
//     principle, and with them the junction offset u P R1. In practice the case filters ambient
//     changes so strongly that this is of no use: a ±2 K ambient swing of 10 min period leaves
//     every four-parameter set with a reciprocal condition ≈ 5e-5 and relative errors ≈ 200 %.
// (4) Practically, with the LMS 200-like values (fast time constant ≈ 12 s, slow ≈ 30 min) the
//     case shows P R2 and the slow time constant well and the fast one only faintly, through the
//     ≈ 12 s delay it adds to every power switch. Separating P from R2 is the weak point: with
//     {R2, C2, P} free it rests on the small R2 C1 term of the slow pole alone (reciprocal
//     condition ≈ 6e-5, relative errors ≈ 150 % for 4 h of 1 Hz readings with 0.035 °C noise). For
//     the same log, the default {R2, C1, C2} gives R2 to ≈ 0.03 %, C2 to ≈ 0.1 % and C1 to ≈ 2.5 %
//     (one standard deviation); C1 and R1 need a log sampled faster than R1 C1 with many power
//     switches.
// A free set whose Jacobian is rank-deficient (reciprocal condition below
// PemOptions::min_reciprocal_condition, which catches the structural cases above at ≈ 1e-14)
// is a NumericalError naming the undetermined direction; so is a fit that leaves a free
// parameter's relative standard error above PemOptions::max_relative_std (the practical cases).
// PemResult::relative_std reports how well each free parameter is determined.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/thermal_model.hpp"

namespace tofcomp::core {

// Algorithm 1's inputs.
struct DatasheetThermalData {
  // Step 1: R1 from the laser's datasheet.
  double r1_k_per_w = 0.0;
  // Step 1: C1 given directly, or else diode volume × density × specific heat.
  std::optional<double> c1_j_per_k;
  double diode_volume_m3 = 0.0;
  double diode_density_kg_per_m3 = 0.0;
  double diode_specific_heat_j_per_kg_k = 0.0;
  // Step 2: C2 = case mass × specific heat of its material.
  double case_mass_kg = 0.0;
  double case_specific_heat_j_per_kg_k = 0.0;
  // Step 3: P = electrical power × efficiency (the paper's 0.5 for generic laser diodes).
  double electrical_power_w = 0.0;
  double efficiency = 0.5;
  // Step 4: R2 = (t^s − t^a) / (u P) at thermal equilibrium with on fraction u (1: always on).
  double equilibrium_case_c = 0.0;
  double equilibrium_ambient_c = 0.0;
  double equilibrium_power_on_fraction = 1.0;
};

// Algorithm 1. Throws InvalidInput naming the first non-positive or non-finite value, an
// efficiency or on fraction outside (0, 1], or an equilibrium case temperature at or below the
// ambient.
ThermalParameters identify_from_datasheet(const DatasheetThermalData& data);

// The parameters, in the order of Jacobian columns and of PemResult::relative_std.
enum class ThermalParameter { kR1 = 0, kR2 = 1, kC1 = 2, kC2 = 3, kPower = 4 };
inline constexpr int kThermalParameterCount = 5;
inline constexpr std::array<ThermalParameter, kThermalParameterCount> kThermalParameters = {
    ThermalParameter::kR1, ThermalParameter::kR2, ThermalParameter::kC1, ThermalParameter::kC2,
    ThermalParameter::kPower};

// "R1", "R2", "C1", "C2", "P".
const char* thermal_parameter_name(ThermalParameter parameter);
// The five values in ThermalParameter order, and back.
std::array<double, kThermalParameterCount> thermal_parameter_values(const ThermalParameters& p);
ThermalParameters thermal_parameters_from(const std::array<double, kThermalParameterCount>& v);

// Which parameters the prediction-error method fits; the others keep their initial values.
// The default is identifiable from a case log with a constant ambient (see above).
struct ThermalParameterMask {
  bool r1 = false;
  bool r2 = true;
  bool c1 = true;
  bool c2 = true;
  bool power = false;
  bool is_free(ThermalParameter parameter) const;
  int count() const;
};

// A log for identification: the on fraction and ambient at each time (held until the next), and
// the case reading t^s at every time. Times in seconds, non-decreasing.
struct CaseTemperatureLog {
  Eigen::VectorXd times_s;
  Eigen::VectorXd power_on_fraction;
  Eigen::VectorXd ambient_c;
  Eigen::VectorXd case_c;
  // Throws InvalidInput unless the four have one length ≥ 1, are finite, the times
  // non-decreasing and the on fractions in [0, 1].
  void validate() const;
};

struct PemOptions {
  ThermalParameterMask free;
  int max_iterations = 100;
  // Converged when an accepted step moves every log-parameter by less than this, or lowers
  // the sum of squares by less than this fraction.
  double step_tolerance = 1e-9;
  double relative_cost_tolerance = 1e-12;
  // At most this change of any log-parameter per iteration (1: a factor e).
  double max_log_step = 1.0;
  // Jacobian σ_min / σ_max below this: the free parameters are not identifiable (NumericalError).
  double min_reciprocal_condition = 1e-7;
  // A free parameter whose relative standard error exceeds this at the optimum is not determined
  // by the log (NumericalError). +∞ disables the check.
  double max_relative_std = 0.5;
};

// What a fit of the thermal network to a case log gives, whichever method made it.
struct ThermalFitResult {
  ThermalParameters parameters;
  Eigen::VectorXd predicted_case_c;  // the output-error prediction at the optimum
  double rms_residual_c = 0.0;
  double paper_fit_percent = 0.0;  // Eq. 26
  double nrmse_fit_percent = 0.0;
  int iterations = 0;
  bool converged = false;
};

struct PemResult : ThermalFitResult {
  // Approximate standard deviation of log p for each free parameter (≈ its relative standard
  // error), from σ̂² (JᵀJ)⁻¹ at the optimum; 0 for fixed parameters. Indexed by ThermalParameter.
  std::array<double, kThermalParameterCount> relative_std{};
};

// The prediction-error fit of the free parameters, starting from `initial` (e.g. Algorithm 1's
// answer). Needs more samples than free parameters. Throws InvalidInput on a bad log, mask or
// options, and NumericalError when the free parameters are not identifiable from this log.
PemResult identify_by_prediction_error(const CaseTemperatureLog& log,
                                       const ThermalParameters& initial,
                                       const PemOptions& options = {});

// The output-error predictor: the case temperature simulated from the log's inputs from the
// initial state above (§8.1: the trained model driven by the test data's inputs).
Eigen::VectorXd predict_case_temperature(const CaseTemperatureLog& log,
                                         const ThermalParameters& parameters);

// The predictor and its exact sensitivities ∂ŷ_k/∂log p for the free parameters (K × n, columns
// in ThermalParameter order), from the sensitivity equations of the zero-order hold.
struct CaseSensitivity {
  Eigen::VectorXd predicted_case_c;
  Eigen::MatrixXd jacobian;
};
CaseSensitivity case_temperature_sensitivity(const CaseTemperatureLog& log,
                                             const ThermalParameters& parameters,
                                             const ThermalParameterMask& free);

// Eq. 26: 100 (1 − Σ(ŷ − y)² / Σ y²). On absolute temperatures in °C the denominator is large,
// so this is near 100 even for a poor fit; prefer the NRMSE fit to compare models. Throws
// InvalidInput on mismatched, empty or non-finite vectors and NumericalError when y is all zero.
double paper_fit_percent(const Eigen::Ref<const Eigen::VectorXd>& predicted,
                         const Eigen::Ref<const Eigen::VectorXd>& measured);

// 100 (1 − ‖y − ŷ‖ / ‖y − ȳ‖): 100 for a perfect fit, 0 for the mean, negative if worse.
// Throws as paper_fit_percent, and NumericalError when y is constant.
double nrmse_fit_percent(const Eigen::Ref<const Eigen::VectorXd>& predicted,
                         const Eigen::Ref<const Eigen::VectorXd>& measured);

}  // namespace tofcomp::core
