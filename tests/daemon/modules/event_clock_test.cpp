// The pipeline's clock (daemon/event_clock.hpp): events never go back in time, and each scan
// gets a time of its own after the last scan's.
#include "daemon/event_clock.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace tofcomp::daemon {
namespace {

TEST(EventClock, CountsSecondsFromItsOrigin) {
  const EventClock clock;
  const auto now = EventClock::Clock::now();
  EXPECT_NEAR(clock.seconds(now + std::chrono::milliseconds(1500)) - clock.seconds(now), 1.5, 1e-9);
  EXPECT_GE(clock.now_s(), 0.0);
}

TEST(EventClock, AnEventBeforeTheLastTakesTheLastOnesTime) {
  EventClock clock;
  EXPECT_EQ(clock.event_at(2.0), 2.0);
  EXPECT_EQ(clock.event_at(1.0), 2.0);  // a reading that reached the loop late
  EXPECT_EQ(clock.last_event_s(), 2.0);
  EXPECT_EQ(clock.event_at(3.0), 3.0);
}

TEST(EventClock, ScansAtOneInstantGetTimesOfTheirOwn) {
  EventClock clock;
  const double first = clock.scan_at(5.0);
  const double second = clock.scan_at(5.0);  // arrived in the same read
  EXPECT_EQ(first, 5.0);
  EXPECT_GT(second, first);
  EXPECT_EQ(clock.last_event_s(), second);
  EXPECT_EQ(clock.event_at(4.0), second);  // a later event is not before the scan
}

}  // namespace
}  // namespace tofcomp::daemon
