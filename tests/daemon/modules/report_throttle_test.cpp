// Reports of a repeated event, one per interval: the first, a new reason at once, and after the
// interval one that says how many were passed over. Times are given, not waited for.
#include "daemon/report_throttle.hpp"

#include <gtest/gtest.h>

namespace tofcomp::daemon {
namespace {

using namespace std::chrono_literals;

TEST(ReportThrottle, OneReportPerIntervalAndReasonWithTheCountPassedOver) {
  ReportThrottle throttle(10s);
  const ReportThrottle::Clock::time_point t0{};
  EXPECT_EQ(throttle.report(t0, "nan"), 0u);
  EXPECT_EQ(throttle.report(t0 + 1s, "nan"), std::nullopt);
  EXPECT_EQ(throttle.report(t0 + 9s, "nan"), std::nullopt);
  EXPECT_EQ(throttle.report(t0 + 10s, "nan"), 2u);
  EXPECT_EQ(throttle.report(t0 + 11s, "nan"), std::nullopt);
  EXPECT_EQ(throttle.report(t0 + 12s, "inf"), 1u);  // another reason: at once
  EXPECT_EQ(throttle.report(t0 + 13s, "inf"), std::nullopt);
}

}  // namespace
}  // namespace tofcomp::daemon
