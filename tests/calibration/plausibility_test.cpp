// The recalibration gate's checks (calibration/plausibility.hpp) on calibrations whose faults are
// known: the bundled calibration passes; one trained on a reference off by 500 mm, one whose
// modes spread over metres, one with modes far apart, one trained at impossible temperatures
// fail, each naming the parameter; offsets and a bias that cancel (they share a constant) pass,
// since the range error they predict is small; the held-out margin is 10 % + 0.05 mm.
#include "calibration/plausibility.hpp"

#include <gtest/gtest.h>

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
