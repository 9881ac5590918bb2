// The daemon's compensation path (realtime/compensation_pipeline.hpp) around a calibration
// swap: what the scanner did before the swap still counts after it.
#include "realtime/compensation_pipeline.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/realtime/realtime_examples.hpp"
#include "tests/support/extensions.hpp"

namespace tofcomp::realtime {
namespace {

std::shared_ptr<core::Calibration> warm_up_calibration(double gamma_mm, double tau_s) {
  auto c = std::make_shared<core::Calibration>(testing::round_calibration());
  c->extension = testing::bias_extension(c->model.mixture, core::Covariate::TimeSincePowerOn,
                                         core::Form::Decay, gamma_mm, tau_s);
  return c;
}

// Power off at 100 s, on again at 200 s; a new calibration at 230 s. A scan at 260 s is 60 s
// after the switch-on, so its bias carries γ·exp(−60/τ), not the daemon's 260 s since start.
TEST(CompensationPipeline, NewCalibrationKeepsTheWarmUpClock) {
  const double gamma = 3.0, tau = 200.0;
  CompensationPipeline pipeline;
  pipeline.set_calibration(warm_up_calibration(gamma, tau), 1);
  for (int s = 0; s < 230; ++s) pipeline.on_case_reading(s, 30.0);
  pipeline.on_power(100.0, false);
  pipeline.on_power(200.0, true);
  const auto swapped = warm_up_calibration(gamma, tau);
  pipeline.set_calibration(swapped, 2);
  RawScan scan;
  scan.time_s = 260.0;
  scan.ranges_mm = {3020.0};
  scan.no_echo = {0};
  const ipc::CompensatedScan out = pipeline.on_scan(scan);
  const ipc::BeamValue& beam = out.beams[0];
  ASSERT_TRUE(std::isfinite(beam.compensated_mm));
  const double expected = 3020.0 - swapped->model.bias_at(out.junction_c) -
                          gamma * std::exp(-60.0 / tau) -
                          swapped->model.mixture.mean[beam.most_probable_mode];
  EXPECT_NEAR(beam.compensated_mm, expected, 1e-9);
}

}  // namespace
}  // namespace tofcomp::realtime
