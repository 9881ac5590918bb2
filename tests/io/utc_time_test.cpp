// The one UTC formatter against dates known independently (the epoch, a leap day, before 1970).
#include "io/utc_time.hpp"

#include <gtest/gtest.h>

#include <regex>

namespace tofcomp::io {
namespace {

constexpr std::int64_t kNs = 1'000'000'000;

TEST(UtcTimestamp, TheEpoch) {
  EXPECT_EQ(utc_timestamp(0, 0), "1970-01-01T00:00:00Z");
  EXPECT_EQ(utc_timestamp(0, 3), "1970-01-01T00:00:00.000Z");
}

// 2024-02-29T12:34:56 UTC is 1709210096 s after the epoch (19782 days and 45296 s).
TEST(UtcTimestamp, ALeapDayWithEveryPrecision) {
  const std::int64_t t = (19782LL * 86400 + 45296) * kNs + 123'456'789;
  EXPECT_EQ(utc_timestamp(t, 0), "2024-02-29T12:34:56Z");
  EXPECT_EQ(utc_timestamp(t, 3), "2024-02-29T12:34:56.123Z");  // truncated, not rounded
  EXPECT_EQ(utc_timestamp(t, 9), "2024-02-29T12:34:56.123456789Z");
  EXPECT_EQ(utc_timestamp(t, 12), "2024-02-29T12:34:56.123456789Z");  // clamped to ns
}

TEST(UtcTimestamp, BeforeTheEpochCountsBack) {
  EXPECT_EQ(utc_timestamp(-1, 9), "1969-12-31T23:59:59.999999999Z");
  EXPECT_EQ(utc_timestamp(-kNs, 0), "1969-12-31T23:59:59Z");
}

TEST(UtcTimestamp, NowHasTheShapeOfASecond) {
  EXPECT_TRUE(std::regex_match(utc_now(), std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")))
      << utc_now();
}

}  // namespace
}  // namespace tofcomp::io
