// The calibration run's power schedule (§8.1) through the GPIO seam: a fake power line records
// each edge and when it came; the schedule runs in a real io_context on its own timers.
#include "daemon/power_cycle_schedule.hpp"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "hal/gpio/gpio_line.hpp"
#include "hal/gpio/power_control.hpp"

namespace tofcomp::daemon {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using Phase = PowerCycleSchedule::Phase;

struct Edge {
  bool on;
  Clock::time_point at;
};

// A power line that records its edges; it fails from the `fail_at`-th set on (0: never).
class RecordingLine : public hal::GpioOutput {
 public:
  RecordingLine(std::vector<Edge>& edges, int fail_at = 0) : edges_(edges), fail_at_(fail_at) {}
  void set(bool active) override {
    if (fail_at_ > 0 && static_cast<int>(edges_.size()) + 1 >= fail_at_) {
      throw hal::GpioError("fake line: set failed", 5);
    }
    edges_.push_back({active, Clock::now()});
    value_ = active;
  }
  bool get() const override { return value_; }
  std::string describe() const override { return "fake power line"; }

 private:
  std::vector<Edge>& edges_;
  int fail_at_;
  bool value_ = true;
};

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

TEST(PowerCycleSchedule, SwitchesOnAndOffForEachCycleWithTheConfiguredDurations) {
  boost::asio::io_context io;
  std::vector<Edge> edges;
  hal::PowerSwitch power(std::make_unique<RecordingLine>(edges), true);
  std::vector<bool> reported;
  std::vector<Phase> ended;
  constexpr double kOn = 0.30, kOff = 0.15;
  PowerCycleSchedule schedule(
      io, power, {3, std::chrono::duration<double>(kOn), std::chrono::duration<double>(kOff)},
      [&](bool on) { reported.push_back(on); },
      [&](Phase phase, const std::string& why) {
        ended.push_back(phase);
        EXPECT_EQ(why, "");
      });
  std::vector<PowerCycleSchedule::Progress> seen;
  boost::asio::steady_timer probe(io);
  std::function<void()> sample = [&] {
    seen.push_back(schedule.progress());
    if (!schedule.running()) return;
    probe.expires_after(20ms);
    probe.async_wait([&](const boost::system::error_code&) { sample(); });
  };
  schedule.start();
  sample();
  io.run_for(5s);

  // on, (off, on) per cycle: cycle 1 on, off, cycle 2 on, off, cycle 3 on, off, on again.
  const std::vector<bool> expected{true, false, true, false, true, false, true};
  ASSERT_EQ(edges.size(), expected.size());
  for (std::size_t i = 0; i < edges.size(); ++i) EXPECT_EQ(edges[i].on, expected[i]) << i;
  EXPECT_EQ(reported, expected);
  // Each on lasts kOn and each off kOff: timers, late by at most a scheduling delay.
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    const double want = edges[i].on ? kOn : kOff;
    const double got = seconds_between(edges[i].at, edges[i + 1].at);
    EXPECT_GE(got, want) << "phase " << i;
    EXPECT_LT(got, want + 0.1) << "phase " << i;
  }
  EXPECT_EQ(ended, std::vector<Phase>{Phase::Finished});
  EXPECT_TRUE(power.is_on());
  EXPECT_EQ(schedule.progress().phase, Phase::Finished);

  // Progress: cycles counted 1 to 3, time left falling from the whole schedule to 0.
  ASSERT_GE(seen.size(), 10u);
  EXPECT_EQ(seen.front().cycle, 1);
  EXPECT_EQ(seen.front().phase, Phase::On);
  EXPECT_NEAR(seen.front().time_left_s, 3 * (kOn + kOff), 0.02);
  int last_cycle = 1;
  double last_left = seen.front().time_left_s;
  for (const auto& p : seen) {
    if (p.phase != Phase::On && p.phase != Phase::Off) continue;
    EXPECT_EQ(p.cycles, 3);
    EXPECT_GE(p.cycle, last_cycle);
    EXPECT_LE(p.time_left_s, last_left + 1e-9);
    last_cycle = p.cycle;
    last_left = p.time_left_s;
  }
  EXPECT_EQ(last_cycle, 3);
}

TEST(PowerCycleSchedule, CancellingWhileOffSwitchesThePowerBackOn) {
  boost::asio::io_context io;
  std::vector<Edge> edges;
  hal::PowerSwitch power(std::make_unique<RecordingLine>(edges), true);
  bool ended = false;
  PowerCycleSchedule schedule(io, power, {2, 100ms, 10s}, nullptr,
                              [&](Phase, const std::string&) { ended = true; });
  schedule.start();
  io.run_for(300ms);  // on, then off for 10 s
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_FALSE(power.is_on());
  EXPECT_EQ(schedule.progress().phase, Phase::Off);
  schedule.cancel();
  EXPECT_TRUE(power.is_on());
  ASSERT_EQ(edges.size(), 3u);
  EXPECT_TRUE(edges.back().on);
  EXPECT_EQ(schedule.progress().phase, Phase::Cancelled);
  io.restart();
  io.run_for(200ms);
  EXPECT_EQ(edges.size(), 3u);  // no timer left
  EXPECT_FALSE(ended);
}

TEST(PowerCycleSchedule, AFailingSwitchEndsTheRunAsFailedNamingTheLine) {
  boost::asio::io_context io;
  std::vector<Edge> edges;
  hal::PowerSwitch power(std::make_unique<RecordingLine>(edges, 2), true);  // off fails
  std::vector<std::pair<Phase, std::string>> ended;
  PowerCycleSchedule schedule(
      io, power, {2, 50ms, 50ms}, nullptr,
      [&](Phase phase, const std::string& why) { ended.emplace_back(phase, why); });
  schedule.start();
  io.run_for(1s);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].first, Phase::Failed);
  EXPECT_NE(ended[0].second.find("switching the power off failed"), std::string::npos)
      << ended[0].second;
  EXPECT_NE(ended[0].second.find("fake line"), std::string::npos) << ended[0].second;
  EXPECT_EQ(edges.size(), 1u);
  EXPECT_FALSE(schedule.running());
}

TEST(PowerCycleSchedule, RefusesNoCyclesAndDurationsThatAreNotPositive) {
  boost::asio::io_context io;
  std::vector<Edge> edges;
  hal::PowerSwitch power(std::make_unique<RecordingLine>(edges), true);
  EXPECT_THROW(PowerCycleSchedule(io, power, {0, 1s, 1s}, nullptr, nullptr), core::InvalidInput);
  EXPECT_THROW(PowerCycleSchedule(io, power, {1, 0s, 1s}, nullptr, nullptr), core::InvalidInput);
  EXPECT_THROW(PowerCycleSchedule(io, power, {1, 1s, -1s}, nullptr, nullptr), core::InvalidInput);
  EXPECT_TRUE(edges.empty());
}

}  // namespace
}  // namespace tofcomp::daemon
