// The host's side of a recording played by its emulator: readings and power changes reach
// the pipeline in the recording's order around the scans, each scan takes its recorded time,
// a scan lost on the line does not hold the events after it forever.
#include "sim/lms200/playback_feed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace tofcomp::sim::lms200 {
namespace {

using namespace std::chrono_literals;

constexpr double kNoEcho = std::numeric_limits<double>::quiet_NaN();

// What the feed handed over, as text: "c<time>:<°C>" and "p<time>:<0|1>".
struct Taken {
  std::vector<std::string> events;
  PlaybackFeed feed{{[this](double t, double c) {
                       events.push_back("c" + std::to_string(t) + ":" + std::to_string(c));
                     },
                     [this](double t, bool on) {
                       events.push_back("p" + std::to_string(t) + ":" + (on ? "1" : "0"));
                     }}};
};

PlaybackEvent reading(double t, double c) {
  return {t, c, std::nullopt, {}};
}
PlaybackEvent power(double t, bool on) {
  return {t, std::nullopt, on, {}};
}
PlaybackEvent scan(double t, std::vector<double> ranges) {
  return {t, std::nullopt, std::nullopt, std::move(ranges)};
}
// A scan with these ranges arrived (NaN: no echo, a 0 range flagged).
std::optional<double> arrive(PlaybackFeed& feed, const std::vector<double>& ranges) {
  std::vector<double> ranges_mm;
  std::vector<std::uint8_t> no_echo;
  for (const double r : ranges) {
    ranges_mm.push_back(std::isnan(r) ? 0.0 : r);
    no_echo.push_back(std::isnan(r) ? 1 : 0);
  }
  return feed.scan_arrived(ranges_mm, no_echo);
}

TEST(PlaybackFeed, HandsOverTheEventsBeforeEachScanThenGivesItsRecordedTime) {
  Taken t;
  t.feed.event_played(reading(0.5, 22.0));
  t.feed.event_played(power(0.6, true));
  t.feed.event_played(scan(0.7, {1000.0, kNoEcho}));
  t.feed.event_played(reading(0.7, 22.5));  // recorded after the scan, at its time
  t.feed.event_played(scan(0.8, {1001.0, 1002.0}));
  // Nothing goes before the scan behind which it was played.
  t.feed.deliver(10s);
  EXPECT_EQ(t.events, (std::vector<std::string>{"c0.500000:22.000000", "p0.600000:1"}));
  EXPECT_EQ(arrive(t.feed, {1000.0, kNoEcho}), 0.7);
  EXPECT_EQ(t.events.size(), 2u);  // the reading after it waits for the next scan
  EXPECT_EQ(arrive(t.feed, {1001.0, 1002.0}), 0.8);
  EXPECT_EQ(t.events.back(), "c0.700000:22.500000");
  // A scan the playback never sent (or one of other ranges) has no recorded time.
  EXPECT_EQ(arrive(t.feed, {1000.0, 1000.0}), std::nullopt);
}

TEST(PlaybackFeed, PassesOverAScanLostOnTheLine) {
  Taken t;
  t.feed.event_played(scan(1.0, {1000.0}));  // lost
  t.feed.event_played(reading(1.05, 23.0));
  t.feed.event_played(scan(1.1, {1001.0}));
  EXPECT_EQ(arrive(t.feed, {1001.0}), 1.1);
  EXPECT_EQ(t.events, (std::vector<std::string>{"c1.050000:23.000000"}));
  // The last scan lost: the events after it go once it is overdue.
  t.feed.event_played(scan(1.2, {1003.0}));
  t.feed.event_played(power(1.3, false));
  t.feed.deliver(10s);
  EXPECT_EQ(t.events.size(), 1u);
  t.feed.deliver(0s);
  EXPECT_EQ(t.events.back(), "p1.300000:0");
}

}  // namespace
}  // namespace tofcomp::sim::lms200
