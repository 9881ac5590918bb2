// The host's estimate of each scan's first ray against the emulated device's true time of it: the
// device paces its bytes at the line's rate and knows when it measured each scan; the host sees
// only when the last byte arrived. Uncorrected, that arrival is late by the telegram's line time
// and the sweep (35 ms at 500 kBd, 210 ms at 38.4 kBd for 0.5° scans).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hal/lms2xx/scan_timing.hpp"
#include "tests/hal/lms2xx/link_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;

// The bounds docs/protocol.md states for the emulator on a pty: the median error within 1 ms, 9
// scans in 10 within 5 ms (a busy host reads the line late now and then: that only ever makes
// the estimate later, never earlier, than the truth).
constexpr double kMedianBoundMs = 1.0;
constexpr double kNinetiethBoundMs = 5.0;
// The device's clock is read just before its first byte goes out: the estimate cannot be earlier
// than the truth by more than the two clocks' reading order.
constexpr double kEarliestMs = -0.5;

struct TimingCase {
  unsigned baud;
  std::size_t scans;
};

class FirstRayTime : public ::testing::TestWithParam<TimingCase> {};

TEST_P(FirstRayTime, IsWithinTheStatedBoundOfTheDevicesTrueTime) {
  emu::EmulatorSettings e;
  e.scenario = default_scenario();
  e.time_scale = 1.0;  // real time: the line's pace is the real one
  lms::DriverSettings d;
  d.baud = GetParam().baud;
  d.ack_timeout = 100ms;
  LinkHarness link(e, d);
  link.start();
  ASSERT_TRUE(link.wait_for_scans(GetParam().scans, 120s));
  link.stop();

  std::vector<double> errors_ms;
  std::size_t next = 0;
  for (const auto& got : link.received()) {
    while (next < link.sent().size() && link.sent()[next].codes != got.codes) ++next;
    ASSERT_LT(next, link.sent().size()) << "a delivered scan matches no scan the device sent";
    const auto truth_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                              link.sent()[next].first_ray.time_since_epoch())
                              .count();
    ASSERT_TRUE(got.rays.known());
    errors_ms.push_back(static_cast<double>(got.rays.first_ray_ns - truth_ns) / 1e6);
    ++next;
  }
  ASSERT_GE(errors_ms.size(), GetParam().scans);
  EXPECT_GT(*std::min_element(errors_ms.begin(), errors_ms.end()), kEarliestMs);
  std::sort(errors_ms.begin(), errors_ms.end());
  const double median = errors_ms[errors_ms.size() / 2];
  const double ninetieth = errors_ms[errors_ms.size() * 9 / 10];
  EXPECT_LT(std::abs(median), kMedianBoundMs);
  EXPECT_LT(ninetieth, kNinetiethBoundMs);
  std::printf(
      "baud %u: %zu scans, first-ray error median %.3f ms, 90th percentile %.3f ms, "
      "max %.3f ms\n",
      GetParam().baud, errors_ms.size(), median, ninetieth, errors_ms.back());
  // The uncorrected arrival would be late by the whole line time and sweep.
  const auto late = hal::lms2xx::line_transfer_time(732, GetParam().baud) +
                    hal::lms2xx::scan_sweep_duration(d.variant);
  const double late_ms = std::chrono::duration<double, std::milli>(late).count();
  EXPECT_GT(late_ms, 10 * kMedianBoundMs);
}

INSTANTIATE_TEST_SUITE_P(Rates, FirstRayTime,
                         ::testing::Values(TimingCase{500000, 150}, TimingCase{38400, 15}),
                         [](const ::testing::TestParamInfo<TimingCase>& param_info) {
                           return "baud" + std::to_string(param_info.param.baud);
                         });

}  // namespace
}  // namespace tofcomp::test
