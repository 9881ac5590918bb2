// The recalibration gate's checks (calibration/plausibility.hpp) on calibrations whose faults are
// known: the bundled calibration passes; one trained on a reference off by 500 mm, one whose
// modes spread over metres, one with modes far apart, one trained at impossible temperatures
// fail, each naming the parameter; offsets and a bias that cancel (they share a constant) pass,
// since the range error they predict is small; the held-out margin is 10 % + 0.05 mm.
#include "calibration/plausibility.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "io/calibration_file.hpp"

namespace tofcomp::calibration {
namespace {

core::Calibration bundled() {
  return io::read_calibration_file(std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml");
}

std::string joined(const std::vector<std::string>& faults) {
  std::string text;
  for (const auto& f : faults) text += f + "\n";
  return text;
}

TEST(Plausibility, TheBundledCalibrationPasses) {
  EXPECT_EQ(joined(implausibilities(bundled())), "");
}

TEST(Plausibility, AReferenceOffByHalfAMetreFails) {
  core::Calibration c = bundled();
  c.model.mixture.mean.array() -= 500.0;  // trained on true_range_mm 500 mm too far
  const std::string faults = joined(implausibilities(c));
  EXPECT_NE(faults.find("it predicts a range error of -50"), std::string::npos) << faults;
  EXPECT_NE(faults.find("beyond the ±50 mm"), std::string::npos) << faults;
}

TEST(Plausibility, OffsetsAndABiasThatCancelPass) {
  // The paper's raw polynomial [t] over a narrow junction range is nearly a constant, which the
  // offsets carry too: here the offsets are +137 and +141 mm and the bias about -139 mm, as a
  // short calibration run can leave them; the errors the calibration predicts are ±2.5 mm.
  core::Calibration c = bundled();
  c.model.basis = core::Basis(
      {core::BasisTerm{core::BasisKind::Polynomial, 1, core::PolynomialForm::RawPower, 0.0}},
      core::TemperatureScaling{27.0, 0.1});
  c.model.theta = Eigen::VectorXd::Constant(1, -139.0 / 27.0);
  c.model.mixture.mean << 137.0, 141.0;
  c.model.trained_junction_c = core::TemperatureRange{26.9, 27.1};
  EXPECT_EQ(joined(implausibilities(c)), "");
  // Shifted by 100 mm, the prediction is beyond the bound.
  c.model.mixture.mean.array() += 100.0;
  EXPECT_NE(joined(implausibilities(c)).find("it predicts a range error of +10"),
            std::string::npos);
}

TEST(Plausibility, SpreadSeparationAndTemperaturesAreBounded) {
  core::Calibration wide = bundled();
  wide.model.mixture.variance[1] = 40.0 * 40.0;
  EXPECT_NE(joined(implausibilities(wide)).find("mode 1's standard deviation is 40.0 mm"),
            std::string::npos);
  core::Calibration apart = bundled();
  apart.model.mixture.mean[0] = -30.0;
  apart.model.mixture.mean[1] = 30.0;
  EXPECT_NE(joined(implausibilities(apart)).find("the modes lie 60.0 mm apart"), std::string::npos);
  core::Calibration hot = bundled();
  hot.model.trained_junction_c = core::TemperatureRange{20.0, 400.0};
  EXPECT_NE(joined(implausibilities(hot)).find("20.0 to 400.0 °C lie outside -40 to 150 °C"),
            std::string::npos);
}

// Calibrations that passed every check of their file and then published nothing or nonsense
// (issue 53): each is refused, naming what is wrong.
TEST(Plausibility, TheThermalNetworkAndTheScalingAreBoundedAsPhysics) {
  const auto faults_of = [](auto change) {
    core::Calibration c = bundled();
    change(c);
    return joined(implausibilities(c));
  };
  const std::string tiny_c1 = faults_of([](core::Calibration& c) { c.thermal.c1_j_per_k = 1e-300; });
  EXPECT_NE(tiny_c1.find("its thermal time constant R1·C1 (junction over case) is"),
            std::string::npos)
      << tiny_c1;
  EXPECT_NE(tiny_c1.find("c1_j_per_k 1e-300"), std::string::npos) << tiny_c1;
  const std::string huge_r1 = faults_of([](core::Calibration& c) { c.thermal.r1_k_per_w = 1e308; });
  EXPECT_NE(huge_r1.find("R1·C1 (junction over case) is inf s"), std::string::npos) << huge_r1;
  EXPECT_NE(huge_r1.find("its thermal steady rise P·R1 (junction over case) is inf K"),
            std::string::npos)
      << huge_r1;
  const std::string hot_case =
      faults_of([](core::Calibration& c) { c.thermal.power_w = 1000.0; });
  EXPECT_NE(hot_case.find("P·R2 (case over ambient) is"), std::string::npos) << hot_case;
  const std::string nan_c2 = faults_of(
      [](core::Calibration& c) { c.thermal.c2_j_per_k = std::numeric_limits<double>::quiet_NaN(); });
  EXPECT_NE(nan_c2.find("R2·C2 (case over ambient) is nan s"), std::string::npos) << nan_c2;
  // A basis scaled to nothing: its bias is no number at any junction temperature.
  const std::string flat = faults_of([](core::Calibration& c) {
    c.model.basis = core::Basis(c.model.basis.terms(), core::TemperatureScaling{
                                                           c.model.basis.scaling().center_c, 1e-300});
  });
  EXPECT_NE(flat.find("its basis is scaled about 26.7963 °C by a half range of 1e-300 °C, outside "
                      "0.0005 to 190 °C"),
            std::string::npos)
      << flat;
}

TEST(Plausibility, TheHeldOutMarginIsTenPercentAndFiveHundredthsOfAMillimetre) {
  HeldOutComparison c{6666, 130, 0.0, 0.100};
  c.new_mae_mm = 0.100 * 1.10 + 0.05 - 1e-9;
  EXPECT_FALSE(held_out_regression(c).has_value());
  c.new_mae_mm = 0.100 * 1.10 + 0.05 + 1e-6;
  const auto worse = held_out_regression(c);
  ASSERT_TRUE(worse.has_value());
  EXPECT_NE(worse->find("on the 6666 held-out ranges (130 windows)"), std::string::npos) << *worse;
  c.new_mae_mm = std::nan("");
  EXPECT_TRUE(held_out_regression(c).has_value());
}

}  // namespace
}  // namespace tofcomp::calibration
