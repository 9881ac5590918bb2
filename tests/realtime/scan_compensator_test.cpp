#include "realtime/scan_compensator.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/covariate_table.hpp"
#include "core/error.hpp"
#include "tests/realtime/realtime_examples.hpp"
#include "tests/support/extensions.hpp"

namespace tofcomp::realtime {
namespace {

JunctionEstimate junction_at(double t) {
  JunctionEstimate j;
  j.valid = true;
  j.junction_c = t;
  j.junction_std_c = 0.1;
  j.case_c = t - 6.0;
  return j;
}

// The daemon's lag node is the offline one (core::first_order_lag) on the same estimates: the
// junction at 40 °C while on, cooling to 25 °C over a 30-minute power-off gap read once a minute
// (no scans then), and back up after. Advanced at the scans alone it would jump the gap at the
// junction after it: here 6.4 K above where the gap's readings put it.
TEST(JunctionLag, FollowsTheJunctionThroughAGapAsTheOfflineLagDoes) {
  constexpr double kTau = 600.0;
  Eigen::VectorXd time_s(121), junction_c(121);
  for (Eigen::Index k = 0; k < time_s.size(); ++k) {
    time_s[k] = 60.0 * static_cast<double>(k);
    const double off_since_s = time_s[k] - 1800.0;  // the power off from 1800 s to 3600 s
    junction_c[k] = time_s[k] < 1800.0   ? 40.0
                    : time_s[k] < 3600.0 ? 25.0 + 15.0 * std::exp(-off_since_s / 300.0)
                                         : 40.0 - 15.0 * std::exp(-(time_s[k] - 3600.0) / 120.0);
  }
  const Eigen::VectorXd offline = core::first_order_lag(time_s, junction_c, kTau);
  JunctionLag every_reading{kTau};
  for (Eigen::Index k = 0; k < time_s.size(); ++k) {
    every_reading.update(time_s[k], junction_c[k]);
    EXPECT_NEAR(every_reading.node_c, offline[k], 1e-12) << "at " << time_s[k] << " s";
  }
  const Eigen::Index first_after_gap = 60;  // 3600 s
  JunctionLag jumped{kTau};
  for (Eigen::Index k = 0; k <= first_after_gap; ++k) {
    if (time_s[k] <= 1800.0 || k == first_after_gap) jumped.update(time_s[k], junction_c[k]);
  }
  EXPECT_GT(jumped.node_c - offline[first_after_gap], 5.0);
  // A late estimate (older than the node) is not taken.
  const double node = every_reading.node_c;
  every_reading.update(10.0, 0.0);
  EXPECT_DOUBLE_EQ(every_reading.node_c, node);
}

core::SlidingWindowOptions incremental() {
  core::SlidingWindowOptions o;
  o.method = core::WindowEm::Incremental;
  return o;
}

// Ranges drawn from Eq. 8 with d = 3000 mm on beam 0 and 1500 mm on beam 2 at a junction of
// 26 °C (bias 13 mm): the compensated ranges are d plus the noise within its mode, and each
// beam's window estimates its own d.
TEST(ScanCompensator, RemovesTheBiasAndTheModeOffset) {
  const auto calibration = std::make_shared<core::Calibration>(testing::round_calibration());
  ASSERT_DOUBLE_EQ(calibration->model.bias_at(26.0), 13.0);  // H(t)θ = 0.5 t
  ScanCompensator compensator(incremental());
  compensator.set_calibration(calibration, 1);
  const auto draw = [&](double d, unsigned seed) {
    return testing::draw_measurements(
        Eigen::VectorXd::Constant(2000, 26.0), d, [](double t) { return 0.5 * t; },
        calibration->model.mixture, seed);
  };
  const auto wall = draw(3000.0, 1);
  const auto near = draw(1500.0, 2);
  double sum_error = 0.0;
  int correct_modes = 0;
  ipc::CompensatedScan last;
  for (Eigen::Index k = 0; k < 2000; ++k) {
    RawScan scan;
    scan.ranges_mm = {wall.range[k], 0.0, near.range[k]};
    scan.no_echo = {0, 1, 0};
    last = compensator.compensate(scan, junction_at(26.0), static_cast<std::uint64_t>(k));
    const ipc::BeamValue& b = last.beams[0];
    EXPECT_EQ(b.flags & ipc::kBeamNoEcho, 0);
    EXPECT_EQ(last.beams[1].flags & ipc::kBeamNoEcho, ipc::kBeamNoEcho);
    EXPECT_TRUE(std::isnan(last.beams[1].compensated_mm));
    EXPECT_DOUBLE_EQ(b.raw_mm, wall.range[k]);
    EXPECT_NEAR(b.mode_posterior[0] + b.mode_posterior[1], 1.0f, 1e-6f);
    correct_modes += b.most_probable_mode == wall.mode[k];
    sum_error += b.compensated_mm - 3000.0;
  }
  // The modes are 4.5 standard deviations apart: most ranges are given their own mode, and
  // the compensated ranges average to d.
  EXPECT_GT(correct_modes, 1900);
  EXPECT_NEAR(sum_error / 2000, 0.0, 0.1);
  EXPECT_NEAR(last.beams[0].window_mm, 3000.0, 4 * last.beams[0].window_std_mm);
  EXPECT_NEAR(last.beams[2].window_mm, 1500.0, 4 * last.beams[2].window_std_mm);
  EXPECT_LT(last.beams[0].window_std_mm, 0.2);
  EXPECT_EQ(last.calibration_id, 1u);
  EXPECT_EQ(last.beams[0].mode_count, 2);
  EXPECT_DOUBLE_EQ(last.junction_c, 26.0);
}

// Beyond the junction temperatures the calibration was trained on, the scan is flagged
// temperature_extrapolated and the bias continues along its tangent at the nearer end; inside,
// no flag and the basis itself.
TEST(ScanCompensator, FlagsAJunctionOutsideTheTrainedRange) {
  core::Calibration c = testing::round_calibration();
  c.model.basis = core::Basis(
      {core::BasisTerm{core::BasisKind::Polynomial, 2, core::PolynomialForm::RawPower, 0.0}},
      core::TemperatureScaling{0.0, 1.0});
  c.model.theta = Eigen::Vector2d(-50.0, 1.0);  // H(t)θ = t² − 50 t = (t − 25)² − 625
  c.model.trained_junction_c = core::TemperatureRange{24.0, 26.0};
  ASSERT_DOUBLE_EQ(c.model.bias_at(25.5), 0.25 - 625.0);
  // The tangent at 26 °C: 1 + 2 (t − 26) − 625 (the basis itself gives 4 − 625 at 27 °C), by a
  // difference over 1 % of the range (error 0.02); at 23 °C the tangent at 24 °C.
  EXPECT_NEAR(c.model.bias_at(27.0), 3.0 - 625.0, 0.03);
  EXPECT_NEAR(c.model.bias_at(23.0), 3.0 - 625.0, 0.03);
  EXPECT_FALSE(c.model.extrapolates(24.0));
  EXPECT_TRUE(c.model.extrapolates(26.01));
  ScanCompensator compensator(incremental());
  compensator.set_calibration(std::make_shared<core::Calibration>(c), 1);
  RawScan scan;
  scan.ranges_mm = {3000.0};
  scan.no_echo = {0};
  const ipc::CompensatedScan inside = compensator.compensate(scan, junction_at(25.5), 0);
  EXPECT_EQ(inside.beams[0].flags & ipc::kBeamTemperatureExtrapolated, 0);
  const ipc::CompensatedScan outside = compensator.compensate(scan, junction_at(27.0), 1);
  EXPECT_EQ(outside.beams[0].flags & ipc::kBeamTemperatureExtrapolated,
            ipc::kBeamTemperatureExtrapolated);
  EXPECT_NEAR(outside.beams[0].raw_mm - outside.beams[0].compensated_mm -
                  c.model.mixture.mean[outside.beams[0].most_probable_mode],
              3.0 - 625.0, 0.03);
}

// Without a calibration, or before any case reading, only the raw ranges are published, with
// the flag that says why; the windows start when both are there.
TEST(ScanCompensator, FlagsWhatIsMissing) {
  ScanCompensator compensator(incremental());
  RawScan scan;
  scan.ranges_mm = {3000.0};
  scan.no_echo = {0};
  ipc::CompensatedScan out = compensator.compensate(scan, junction_at(26.0), 0);
  EXPECT_EQ(out.beams[0].flags, ipc::kBeamUncalibrated);
  EXPECT_TRUE(std::isnan(out.beams[0].compensated_mm));
  EXPECT_EQ(out.calibration_id, 0u);

  compensator.set_calibration(std::make_shared<core::Calibration>(testing::round_calibration()), 7);
  out = compensator.compensate(scan, JunctionEstimate{}, 1);
  EXPECT_EQ(out.beams[0].flags, ipc::kBeamTemperatureStale);
  EXPECT_TRUE(std::isnan(out.junction_c));
  EXPECT_TRUE(std::isnan(out.beams[0].compensated_mm));

  out = compensator.compensate(scan, junction_at(26.0), 2);
  EXPECT_EQ(out.beams[0].flags, ipc::kBeamWindowRestarting);
  EXPECT_DOUBLE_EQ(out.beams[0].compensated_mm, 3000.0 - 13.0 - (-2.0));
  EXPECT_TRUE(std::isnan(out.beams[0].window_mm));
  EXPECT_EQ(out.calibration_id, 7u);

  JunctionEstimate stale = junction_at(26.0);
  stale.stale = true;
  out = compensator.compensate(scan, stale, 3);
  EXPECT_TRUE(out.beams[0].flags & ipc::kBeamTemperatureStale);
  EXPECT_FALSE(std::isnan(out.beams[0].compensated_mm));  // still compensated, by prediction
}

// An object steps in front of the wall: the beam's window restarts on it.
TEST(ScanCompensator, FlagsAChangeOfScene) {
  const auto calibration = std::make_shared<core::Calibration>(testing::round_calibration());
  ScanCompensator compensator(incremental());
  compensator.set_calibration(calibration, 1);
  const auto wall = testing::draw_measurements(
      Eigen::VectorXd::Constant(500, 26.0), 3000.0, [](double t) { return 0.5 * t; },
      calibration->model.mixture, 5);
  const auto object = testing::draw_measurements(
      Eigen::VectorXd::Constant(300, 26.0), 2500.0, [](double t) { return 0.5 * t; },
      calibration->model.mixture, 6);
  int changes = 0;
  ipc::CompensatedScan out;
  for (Eigen::Index k = 0; k < 800; ++k) {
    RawScan scan;
    scan.ranges_mm = {k < 500 ? wall.range[k] : object.range[k - 500]};
    scan.no_echo = {0};
    out = compensator.compensate(scan, junction_at(26.0), static_cast<std::uint64_t>(k));
    if (out.beams[0].flags & ipc::kBeamChangeDetected) {
      ++changes;
      EXPECT_GE(k, 500);
      EXPECT_LE(k, 503);
    }
  }
  EXPECT_EQ(changes, 1);
  EXPECT_NEAR(out.beams[0].window_mm, 2500.0, 4 * out.beams[0].window_std_mm);
}

TEST(ScanCompensator, RefusesWhatItCannotUse) {
  ScanCompensator compensator;
  core::Calibration five = testing::round_calibration();
  five.model.mixture =
      testing::mixture({-4.0, -2.0, 0.0, 2.0, 4.0}, {1, 1, 1, 1, 1}, {0.2, 0.2, 0.2, 0.2, 0.2});
  EXPECT_THROW(compensator.set_calibration(std::make_shared<core::Calibration>(five), 1),
               core::InvalidInput);
  RawScan scan;
  scan.ranges_mm = {1.0, 2.0};
  scan.no_echo = {0};
  EXPECT_THROW(compensator.compensate(scan, junction_at(26.0), 0), core::InvalidInput);
  scan.no_echo = {0, 0};
  scan.ranges_mm[1] = NAN;
  EXPECT_THROW(compensator.compensate(scan, junction_at(26.0), 0), core::InvalidInput);
}

// A calibration's extension, by hand: the bias term is removed with the paper's bias (time
// drift: hours of the pipeline's clock; heating hysteresis: the junction estimate's rate;
// warm-up: exp(−t_on/τ); a mode's offset moving with the junction temperature), and a range the
// outlier component takes is flagged without moving the window.
TEST(ScanCompensator, AppliesTheCalibrationsExtension) {
  const auto with_bias = [](core::Covariate covariate, core::Form form, double gamma,
                            double tau = 0.0) {
    auto c = std::make_shared<core::Calibration>(testing::round_calibration());
    c->extension = testing::bias_extension(c->model.mixture, covariate, form, gamma, tau);
    return c;
  };
  const auto with_structure = [](core::Parameter structure) {
    auto c = std::make_shared<core::Calibration>(testing::round_calibration());
    c->extension = testing::structure_extension(c->model.mixture, structure);
    return c;
  };
  // 26 °C: the paper's bias is 13 mm. The first range of a window is given mode 0 (its residual
  // at d̂ = x − Σπμ is Σπμ = 0.025 mm, nearer μ_0 = −2 than μ_1 = 2.5), so it is compensated
  // by y − bias − μ_0.
  RawScan scan;
  scan.no_echo = {0};
  {
    ScanCompensator compensator(incremental());
    compensator.set_calibration(with_bias(core::Covariate::Time, core::Form::Linear, 4.0), 1);
    scan.time_s = 9000.0;                    // 2.5 h: γ·c = 10 mm
    scan.ranges_mm = {3000.0 + 23.0 - 2.0};  // d + bias + μ_0
    const ipc::CompensatedScan out = compensator.compensate(scan, junction_at(26.0), 0);
    EXPECT_EQ(out.beams[0].most_probable_mode, 0);
    EXPECT_DOUBLE_EQ(out.beams[0].compensated_mm, 3000.0);
  }
  {
    ScanCompensator compensator(incremental());
    compensator.set_calibration(with_bias(core::Covariate::HeatingRate, core::Form::Linear, 2.0),
                                1);
    JunctionEstimate heating = junction_at(26.0);
    heating.heating_rate_c_per_min = 1.5;  // γ·c = 3 mm
    scan.ranges_mm = {3000.0 + 16.0 - 2.0};
    const ipc::CompensatedScan out = compensator.compensate(scan, heating, 0);
    EXPECT_DOUBLE_EQ(out.beams[0].compensated_mm, 3000.0);
  }
  {
    auto c = with_bias(core::Covariate::TimeSincePowerOn, core::Form::Decay, 3.0, 200.0);
    ScanCompensator compensator(incremental());
    compensator.set_calibration(c, 1);
    JunctionEstimate warming = junction_at(26.0);
    warming.time_since_power_on_s = 200.0 * std::log(3.0);  // γ·exp(−t_on/τ) = 1 mm
    scan.ranges_mm = {3000.0 + 14.0 - 2.0};
    const ipc::CompensatedScan out = compensator.compensate(scan, warming, 0);
    EXPECT_NEAR(out.beams[0].compensated_mm, 3000.0, 1e-9);
  }
  {
    // Mode 1's offset 0.5 mm higher per °C above 25 °C: at 26 °C mode 1 sits at −2 + 0.5.
    auto c = std::make_shared<core::Calibration>(testing::round_calibration());
    core::ModelExtension x = testing::structure_extension(c->model.mixture, core::Parameter::ModeOffset);
    core::Term t = testing::raw_bias_term(core::Covariate::JunctionTemperature, core::Form::Linear);
    t.parameter = core::Parameter::ModeOffset;
    t.mode = 0;
    t.centre = 25.0;
    x.effects = {t.label()};
    x.mean_terms.push_back({t, Eigen::VectorXd::Constant(1, 0.5)});
    c->extension = x;
    ScanCompensator compensator(incremental());
    compensator.set_calibration(c, 1);
    scan.ranges_mm = {3000.0 + 13.0 - 2.0 + 0.5};
    const ipc::CompensatedScan out = compensator.compensate(scan, junction_at(26.0), 0);
    EXPECT_EQ(out.beams[0].most_probable_mode, 0);
    EXPECT_NEAR(out.beams[0].compensated_mm, 3000.0, 1e-9);
  }
  {
    auto c = with_structure(core::Parameter::Outliers);
    c->extension->extended_mixture.outlier_weight = 0.02;
    c->extension->extended_mixture.outlier_density = 1.0 / 200.0;
    ScanCompensator compensator(incremental());
    compensator.set_calibration(c, 1);
    const auto wall = testing::draw_measurements(
        Eigen::VectorXd::Constant(300, 26.0), 3000.0, [](double t) { return 0.5 * t; },
        c->model.mixture, 5);
    ipc::CompensatedScan out;
    int flagged = 0;
    for (Eigen::Index k = 0; k < 300; ++k) {
      scan.ranges_mm = {wall.range[k]};
      out = compensator.compensate(scan, junction_at(26.0), static_cast<std::uint64_t>(k));
      flagged += (out.beams[0].flags & ipc::kBeamOutlier) != 0;
    }
    EXPECT_EQ(flagged, 0);
    const double before = out.beams[0].window_mm;
    scan.ranges_mm = {3013.0 + 80.0};
    out = compensator.compensate(scan, junction_at(26.0), 300);
    EXPECT_EQ(out.beams[0].flags, ipc::kBeamOutlier);
    EXPECT_NEAR(out.beams[0].window_mm, before, 0.05);
  }
  // An invalid extension is refused and the old calibration stays.
  ScanCompensator compensator(incremental());
  auto bad = with_structure(core::Parameter::Markov);
  bad->extension->extended_mixture.transition = Eigen::MatrixXd::Constant(2, 2, 0.7);
  EXPECT_THROW(compensator.set_calibration(bad, 1), core::InvalidInput);
  EXPECT_EQ(compensator.calibration(), nullptr);
}

}  // namespace
}  // namespace tofcomp::realtime
