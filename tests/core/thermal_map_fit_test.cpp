// The thermal fit with the datasheet as a prior: it answers wherever the prediction-error method
// refuses, recovers what a case log shows, and holds at the datasheet exactly what the log cannot
// show (the heat scale of the header of core/thermal_identification.hpp), on logs simulated from
// known parameters.
#include "core/thermal_map_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "tests/support/thermal_examples.hpp"

namespace tofcomp::core {
namespace {

using testing::cycling_log;

// Algorithm 1's answer for a unit that is not the one logged: every value off by a factor
// between 0.7 and 1.4.
ThermalParameters mistaken_datasheet(const ThermalParameters& truth) {
  return {truth.r1_k_per_w * 1.3, truth.r2_k_per_w * 0.7, truth.c1_j_per_k * 1.4,
          truth.c2_j_per_k * 0.8, truth.power_w * 1.2};
}

// (P, R1, R2, C1, C2) → (sP, R1/s, R2/s, sC1, sC2) changes no temperature: the coordinate
// −log R1 − log R2 + log C1 + log C2 + log P is the one no log shows.
double heat_scale_coordinate(const ThermalParameters& p) {
  return -std::log(p.r1_k_per_w) - std::log(p.r2_k_per_w) + std::log(p.c1_j_per_k) +
         std::log(p.c2_j_per_k) + std::log(p.power_w);
}

TEST(ThermalMapFit, RecoversWhatTheCaseShowsFromAMistakenDatasheet) {
  const ThermalParameters truth = lms200_example_parameters();
  for (const unsigned seed : {21u, 22u, 23u}) {
    const CaseTemperatureLog log = cycling_log(truth, 4 * 3600, seed, 0.03, true);
    const MapFitResult r = identify_with_datasheet_prior(log, mistaken_datasheet(truth));
    EXPECT_TRUE(r.converged) << seed;
    // The case's gain P R2 and slow time constant R2 C2 (constant ambient: header, (2)).
    EXPECT_NEAR(r.parameters.power_w * r.parameters.r2_k_per_w / (truth.power_w * truth.r2_k_per_w),
                1.0, 0.01)
        << seed;
    EXPECT_NEAR(
        r.parameters.r2_k_per_w * r.parameters.c2_j_per_k / (truth.r2_k_per_w * truth.c2_j_per_k),
        1.0, 0.02)
        << seed;
    // Quantization to 0.0625 °C and 0.03 °C of noise: the residual is that and no more.
    EXPECT_NEAR(r.rms_residual_c, std::sqrt(0.03 * 0.03 + 0.0625 * 0.0625 / 12.0), 0.005) << seed;
  }
}

TEST(ThermalMapFit, HoldsTheHeatScaleAtTheDatasheet) {
  const ThermalParameters truth = lms200_example_parameters();
  const ThermalParameters datasheet = mistaken_datasheet(truth);
  const MapFitResult r =
      identify_with_datasheet_prior(cycling_log(truth, 4 * 3600, 31, 0.03, true), datasheet);
  ASSERT_FALSE(r.prior_held_directions.empty());
  const PriorHeldDirection& weakest = r.prior_held_directions.front();
  EXPECT_LT(weakest.data_over_prior, 1e-6);
  const double s = 1.0 / std::sqrt(5.0);
  const std::array<double, kThermalParameterCount> heat_scale{-s, -s, s, s, s};
  double dot = 0.0;
  for (std::size_t i = 0; i < heat_scale.size(); ++i)
    dot += heat_scale[i] * weakest.log_direction[i];
  EXPECT_GT(std::abs(dot), 0.999);
  // The data pull nowhere along it: the estimate keeps the datasheet's coordinate.
  EXPECT_NEAR(heat_scale_coordinate(r.parameters), heat_scale_coordinate(datasheet), 1e-4);
  // And no parameter alone is all data: a fifth of each one's prior variance is that direction.
  for (const double share : r.data_share) EXPECT_LT(share, 0.81);
}

// The prediction-error method refuses a log that cannot determine what it frees; the prior fit
// answers, and says the data showed nothing of an idle log.
TEST(ThermalMapFit, AnswersWhereThePredictionErrorMethodRefuses) {
  const ThermalParameters truth = lms200_example_parameters();
  CaseTemperatureLog idle = cycling_log(truth, 3 * 3600, 6, 0.03, true);
  idle.power_on_fraction.setZero();
  idle.case_c.setConstant(22.0);
  idle.case_c[1] = 22.0625;  // one reading off, so that the NRMSE fit is defined
  PemOptions all_free;
  all_free.free = {.r1 = true, .r2 = true, .c1 = true, .c2 = true, .power = true};
  EXPECT_THROW(identify_by_prediction_error(idle, truth, all_free), NumericalError);
  const ThermalParameters datasheet = mistaken_datasheet(truth);
  const MapFitResult r = identify_with_datasheet_prior(idle, datasheet);
  const auto fitted = thermal_parameter_values(r.parameters);
  const auto prior = thermal_parameter_values(datasheet);
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    EXPECT_NEAR(fitted[i] / prior[i], 1.0, 1e-3) << thermal_parameter_name(kThermalParameters[i]);
    EXPECT_TRUE(r.held[i]);
    EXPECT_NEAR(r.relative_std[i], MapFitOptions{}.prior_log_std, 1e-3);
  }
}

TEST(ThermalMapFit, RejectsBadArguments) {
  const ThermalParameters truth = lms200_example_parameters();
  const CaseTemperatureLog log = cycling_log(truth, 100, 8, 0.03, false);
  MapFitOptions bad;
  bad.prior_log_std = 0.0;
  EXPECT_THROW(identify_with_datasheet_prior(log, truth, bad), InvalidInput);
  bad = MapFitOptions{};
  bad.held_below_data_share = 1.5;
  EXPECT_THROW(identify_with_datasheet_prior(log, truth, bad), InvalidInput);
  CaseTemperatureLog one = log;
  for (Eigen::VectorXd* v : {&one.times_s, &one.power_on_fraction, &one.ambient_c, &one.case_c}) {
    v->conservativeResize(1);
  }
  EXPECT_THROW(identify_with_datasheet_prior(one, truth), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
