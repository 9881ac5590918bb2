#include "core/thermal_identification.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "core/error.hpp"
#include "tests/support/thermal_examples.hpp"

namespace tofcomp::core {
namespace {

using testing::cycling_log;

ThermalParameters scaled(ThermalParameters p, double r2, double c1, double c2) {
  p.r2_k_per_w *= r2;
  p.c1_j_per_k *= c1;
  p.c2_j_per_k *= c2;
  return p;
}

TEST(ThermalIdentification, Algorithm1OnHandComputedNumbers) {
  DatasheetThermalData d;
  d.r1_k_per_w = 0.2;
  d.diode_volume_m3 = 1e-9;                  // a 1 mm³ chip
  d.diode_density_kg_per_m3 = 5300.0;        // GaAs
  d.diode_specific_heat_j_per_kg_k = 330.0;  // GaAs
  d.case_mass_kg = 4.5;                      // LMS 200
  d.case_specific_heat_j_per_kg_k = 900.0;   // aluminium
  d.electrical_power_w = 20.0;               // LMS 200
  d.equilibrium_case_c = 26.8;
  d.equilibrium_ambient_c = 22.0;
  ThermalParameters p = identify_from_datasheet(d);
  EXPECT_DOUBLE_EQ(p.r1_k_per_w, 0.2);
  EXPECT_NEAR(p.c1_j_per_k, 1.749e-3, 1e-15);
  EXPECT_DOUBLE_EQ(p.c2_j_per_k, 4050.0);
  EXPECT_DOUBLE_EQ(p.power_w, 10.0);       // 20 W × 0.5
  EXPECT_NEAR(p.r2_k_per_w, 0.48, 1e-14);  // (26.8 − 22) / 10
  d.c1_j_per_k = 60.0;                     // given directly: the volume is not used
  d.equilibrium_power_on_fraction = 0.5;   // half the heat at rest: R2 = 4.8 / 5
  p = identify_from_datasheet(d);
  EXPECT_DOUBLE_EQ(p.c1_j_per_k, 60.0);
  EXPECT_NEAR(p.r2_k_per_w, 0.96, 1e-14);
}

TEST(ThermalIdentification, Algorithm1RejectsBadValues) {
  DatasheetThermalData d;
  d.r1_k_per_w = 0.2;
  d.c1_j_per_k = 60.0;
  d.case_mass_kg = -4.5;
  d.case_specific_heat_j_per_kg_k = 900.0;
  d.electrical_power_w = 20.0;
  d.equilibrium_case_c = 26.8;
  d.equilibrium_ambient_c = 22.0;
  try {
    identify_from_datasheet(d);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("case_mass_kg"), std::string::npos) << e.what();
  }
  d.case_mass_kg = 4.5;
  d.equilibrium_case_c = 22.0;  // at ambient: no heat flows, R2 undefined
  EXPECT_THROW(identify_from_datasheet(d), InvalidInput);
  d.equilibrium_case_c = 21.0;
  EXPECT_THROW(identify_from_datasheet(d), InvalidInput);
  d.equilibrium_case_c = 26.8;
  d.efficiency = 1.5;
  EXPECT_THROW(identify_from_datasheet(d), InvalidInput);
  d.efficiency = 0.5;
  d.c1_j_per_k.reset();  // and no diode volume
  EXPECT_THROW(identify_from_datasheet(d), InvalidInput);
  d.c1_j_per_k = 60.0;
  EXPECT_NO_THROW(identify_from_datasheet(d));
}

// (P, R1, R2, C1, C2) → (sP, R1/s, R2/s, sC1, sC2) changes neither temperature: the reason
// the five parameters can never be identified together.
TEST(ThermalIdentification, HeatScaleLeavesTemperaturesUnchanged) {
  const ThermalParameters p = lms200_example_parameters();
  ThermalParameters q = p;
  q.power_w *= 3.0;
  q.r1_k_per_w /= 3.0;
  q.r2_k_per_w /= 3.0;
  q.c1_j_per_k *= 3.0;
  q.c2_j_per_k *= 3.0;
  const CaseTemperatureLog log = cycling_log(p, 3000, 1, 0.0, false, 1.0);
  const Eigen::Vector2d x0(23.0, 25.0);
  const ThermalTrajectory a =
      simulate_at_times(p, x0, log.times_s, log.power_on_fraction, log.ambient_c);
  const ThermalTrajectory b =
      simulate_at_times(q, x0, log.times_s, log.power_on_fraction, log.ambient_c);
  EXPECT_LT((a.case_c - b.case_c).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((a.junction_c - b.junction_c).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(ThermalIdentification, PredictorStartsAtRestWithTheFirstReading) {
  const ThermalParameters p = lms200_example_parameters();
  CaseTemperatureLog log = cycling_log(p, 500, 2, 0.05, false);
  log.power_on_fraction[0] = 1.0;
  const Eigen::VectorXd predicted = predict_case_temperature(log, p);
  const Eigen::Vector2d x0(log.case_c[0], log.case_c[0] + p.power_w * p.r1_k_per_w);
  const ThermalTrajectory t =
      simulate_at_times(p, x0, log.times_s, log.power_on_fraction, log.ambient_c);
  EXPECT_LT((predicted - t.case_c).norm(), 1e-12);
}

// The analytic sensitivities agree with central differences of the predictor.
TEST(ThermalIdentification, SensitivityMatchesFiniteDifferences) {
  const ThermalParameters p = lms200_example_parameters();
  CaseTemperatureLog log = cycling_log(p, 1500, 3, 0.02, false, 1.0);
  log.power_on_fraction[0] = 1.0;  // so the initial junction depends on R1 and P
  for (Eigen::Index i = 0; i < log.times_s.size(); ++i) {
    log.times_s[i] = 1.3 * static_cast<double>(i) + 0.4 * std::sin(static_cast<double>(i));
  }
  ThermalParameterMask all;
  all.r1 = all.r2 = all.c1 = all.c2 = all.power = true;
  const CaseSensitivity s = case_temperature_sensitivity(log, p, all);
  EXPECT_LT((s.predicted_case_c - predict_case_temperature(log, p)).norm(), 1e-10);
  const double h = 1e-4;
  for (int j = 0; j < kThermalParameterCount; ++j) {
    auto nudged = [&](double factor) {
      ThermalParameters q = p;
      double* value[] = {&q.r1_k_per_w, &q.r2_k_per_w, &q.c1_j_per_k, &q.c2_j_per_k, &q.power_w};
      *value[j] *= factor;
      return predict_case_temperature(log, q);
    };
    const Eigen::VectorXd difference = (nudged(std::exp(h)) - nudged(std::exp(-h))) / (2.0 * h);
    // Central differences carry ≈ h² truncation and ≈ 1e-15 · 25 °C / h rounding error.
    EXPECT_LT((s.jacobian.col(j) - difference).cwiseAbs().maxCoeff(),
              1e-6 * difference.cwiseAbs().maxCoeff() + 1e-9)
        << j;
  }
}

TEST(ThermalIdentification, PemRecoversNoiseFreeParameters) {
  const ThermalParameters truth = lms200_example_parameters();
  const CaseTemperatureLog log = cycling_log(truth, 4 * 3600, 4, 0.0, false);
  const PemResult r = identify_by_prediction_error(log, scaled(truth, 1.3, 0.5, 0.7));
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.parameters.r2_k_per_w / truth.r2_k_per_w, 1.0, 1e-6);
  EXPECT_NEAR(r.parameters.c1_j_per_k / truth.c1_j_per_k, 1.0, 1e-6);
  EXPECT_NEAR(r.parameters.c2_j_per_k / truth.c2_j_per_k, 1.0, 1e-6);
  EXPECT_EQ(r.parameters.r1_k_per_w, truth.r1_k_per_w);  // fixed by the mask
  EXPECT_EQ(r.parameters.power_w, truth.power_w);
  EXPECT_LT(r.rms_residual_c, 1e-6);
  EXPECT_GT(r.nrmse_fit_percent, 99.99);
}

// Four hours at 1 Hz, σ = 0.03 °C noise quantized to 0.0625 °C, from a start 20-50 % off:
// R2 within 1 %, C2 within 2 %, C1 (seen only through the 12 s junction lag) within 25 %, and
// each error within 5 of the reported relative standard deviations.
TEST(ThermalIdentification, PemRecoversParametersFromNoisyQuantizedLogs) {
  const ThermalParameters truth = lms200_example_parameters();
  for (const unsigned seed : {11u, 12u, 13u, 14u}) {
    const CaseTemperatureLog log = cycling_log(truth, 4 * 3600, seed, 0.03, true);
    const PemResult r = identify_by_prediction_error(log, scaled(truth, 1.2, 1.5, 0.8));
    EXPECT_TRUE(r.converged) << seed;
    const double e_r2 = std::log(r.parameters.r2_k_per_w / truth.r2_k_per_w);
    const double e_c1 = std::log(r.parameters.c1_j_per_k / truth.c1_j_per_k);
    const double e_c2 = std::log(r.parameters.c2_j_per_k / truth.c2_j_per_k);
    EXPECT_LT(std::abs(e_r2), 0.01) << seed;
    EXPECT_LT(std::abs(e_c1), 0.25) << seed;
    EXPECT_LT(std::abs(e_c2), 0.02) << seed;
    const auto& sd = r.relative_std;
    EXPECT_LT(std::abs(e_r2), 5.0 * sd[static_cast<int>(ThermalParameter::kR2)]) << seed;
    EXPECT_LT(std::abs(e_c1), 5.0 * sd[static_cast<int>(ThermalParameter::kC1)]) << seed;
    EXPECT_LT(std::abs(e_c2), 5.0 * sd[static_cast<int>(ThermalParameter::kC2)]) << seed;
    EXPECT_EQ(sd[static_cast<int>(ThermalParameter::kR1)], 0.0);
    EXPECT_NEAR(r.rms_residual_c, std::sqrt(0.03 * 0.03 + 0.0625 * 0.0625 / 12.0), 0.005) << seed;
  }
}

// Other identifiable triples than the default.
TEST(ThermalIdentification, PemRecoversOtherIdentifiableSubsets) {
  const ThermalParameters truth = lms200_example_parameters();
  const CaseTemperatureLog log = cycling_log(truth, 4 * 3600, 5, 0.0, false);
  PemOptions options;
  options.free = {.r1 = false, .r2 = true, .c1 = false, .c2 = true, .power = true};
  ThermalParameters start = truth;
  start.power_w *= 0.8;
  start.c2_j_per_k *= 1.3;
  PemResult r = identify_by_prediction_error(log, start, options);
  EXPECT_NEAR(r.parameters.power_w / truth.power_w, 1.0, 1e-6);
  EXPECT_NEAR(r.parameters.c2_j_per_k / truth.c2_j_per_k, 1.0, 1e-6);
  options.free = {.r1 = true, .r2 = true, .c1 = true, .c2 = false, .power = false};
  start = truth;
  start.r1_k_per_w *= 1.5;
  start.c1_j_per_k *= 0.7;
  r = identify_by_prediction_error(log, start, options);
  EXPECT_NEAR(r.parameters.r1_k_per_w / truth.r1_k_per_w, 1.0, 1e-6);
  EXPECT_NEAR(r.parameters.c1_j_per_k / truth.c1_j_per_k, 1.0, 1e-6);
}

TEST(ThermalIdentification, NonIdentifiableMasksAreNumericalErrors) {
  const ThermalParameters truth = lms200_example_parameters();
  const CaseTemperatureLog log = cycling_log(truth, 3 * 3600, 6, 0.03, true);
  PemOptions options;
  options.free = {.r1 = true, .r2 = true, .c1 = true, .c2 = true, .power = true};
  try {
    identify_by_prediction_error(log, truth, options);
    FAIL() << "expected NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("not identifiable"), std::string::npos) << e.what();
  }
  options.free = {.r1 = true, .r2 = false, .c1 = true, .c2 = true, .power = false};
  EXPECT_THROW(identify_by_prediction_error(log, truth, options), NumericalError);
  options.free = {.r1 = true, .r2 = true, .c1 = true, .c2 = true, .power = false};
  EXPECT_THROW(identify_by_prediction_error(log, truth, options), NumericalError);
  // No excitation: the device off in a steady room, the case at ambient. Nothing shows.
  CaseTemperatureLog idle = log;
  idle.power_on_fraction.setZero();
  idle.case_c.setConstant(22.0);
  options.free = {.r1 = false, .r2 = true, .c1 = true, .c2 = false, .power = false};
  EXPECT_THROW(identify_by_prediction_error(idle, truth, options), NumericalError);
}

// {R2, C2, P} is identifiable in theory but not from 4 h of noisy 1 Hz readings: a clear error,
// or, with the check disabled, a large reported uncertainty.
TEST(ThermalIdentification, PracticallyUndeterminedParametersAreNumericalErrors) {
  const ThermalParameters truth = lms200_example_parameters();
  const CaseTemperatureLog log = cycling_log(truth, 4 * 3600, 9, 0.03, true);
  PemOptions options;
  options.free = {.r1 = false, .r2 = true, .c1 = false, .c2 = true, .power = true};
  try {
    identify_by_prediction_error(log, truth, options);
    FAIL() << "expected NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("does not determine"), std::string::npos) << e.what();
  }
  options.max_relative_std = std::numeric_limits<double>::infinity();
  const PemResult r = identify_by_prediction_error(log, truth, options);
  EXPECT_GT(r.relative_std[static_cast<int>(ThermalParameter::kPower)], 0.5);
  EXPECT_TRUE(std::isfinite(r.parameters.power_w));
}

// A varying ambient adds the zero R1 C1 s + 1: four parameters become identifiable in principle.
TEST(ThermalIdentification, VaryingAmbientRevealsAFourthCombination) {
  const ThermalParameters truth = lms200_example_parameters();
  ThermalParameterMask four;
  four.r1 = four.r2 = four.c1 = four.c2 = true;
  auto reciprocal_condition = [&](double ambient_swing) {
    const CaseTemperatureLog log = cycling_log(truth, 3 * 3600, 7, 0.0, false, ambient_swing);
    const Eigen::MatrixXd j = case_temperature_sensitivity(log, truth, four).jacobian;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j);
    return svd.singularValues().minCoeff() / svd.singularValues().maxCoeff();
  };
  EXPECT_LT(reciprocal_condition(0.0), 1e-10);
  EXPECT_GT(reciprocal_condition(2.0), 1e-6);
}

TEST(ThermalIdentification, PemRejectsBadArguments) {
  const ThermalParameters truth = lms200_example_parameters();
  CaseTemperatureLog log = cycling_log(truth, 100, 8, 0.03, false);
  PemOptions options;
  options.free = {.r1 = false, .r2 = false, .c1 = false, .c2 = false, .power = false};
  EXPECT_THROW(identify_by_prediction_error(log, truth, options), InvalidInput);
  CaseTemperatureLog short_log = log;
  short_log.times_s = log.times_s.head(3);
  short_log.power_on_fraction = log.power_on_fraction.head(3);
  short_log.ambient_c = log.ambient_c.head(3);
  short_log.case_c = log.case_c.head(3);
  EXPECT_THROW(identify_by_prediction_error(short_log, truth), InvalidInput);
  log.case_c[5] = std::nan("");
  EXPECT_THROW(identify_by_prediction_error(log, truth), InvalidInput);
}

TEST(ThermalFitMetrics, HandComputed) {
  const Eigen::Vector3d predicted(1.0, 2.0, 3.0);
  const Eigen::Vector3d measured(1.0, 2.0, 5.0);
  // Σ(ŷ − y)² = 4, Σy² = 30.
  EXPECT_DOUBLE_EQ(paper_fit_percent(predicted, measured), 100.0 * (1.0 - 4.0 / 30.0));
  // ȳ = 8/3, ‖y − ȳ‖² = (25 + 4 + 49)/9, ‖y − ŷ‖ = 2.
  EXPECT_DOUBLE_EQ(nrmse_fit_percent(predicted, measured),
                   100.0 * (1.0 - 2.0 / std::sqrt(78.0 / 9.0)));
  EXPECT_DOUBLE_EQ(nrmse_fit_percent(measured, measured), 100.0);
  EXPECT_DOUBLE_EQ(nrmse_fit_percent(Eigen::Vector3d::Constant(8.0 / 3.0), measured), 0.0);
}

TEST(ThermalFitMetrics, DegenerateInput) {
  EXPECT_THROW(paper_fit_percent(Eigen::Vector2d(1, 2), Eigen::Vector2d(0, 0)), NumericalError);
  EXPECT_THROW(nrmse_fit_percent(Eigen::Vector2d(1, 2), Eigen::Vector2d(3, 3)), NumericalError);
  EXPECT_THROW(paper_fit_percent(Eigen::Vector2d(1, 2), Eigen::Vector3d(1, 2, 3)), InvalidInput);
  EXPECT_THROW(nrmse_fit_percent(Eigen::VectorXd(0), Eigen::VectorXd(0)), InvalidInput);
  EXPECT_THROW(paper_fit_percent(Eigen::Vector2d(1, NAN), Eigen::Vector2d(1, 2)), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
