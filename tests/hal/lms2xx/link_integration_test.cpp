// The host driver brings up the emulated LMS 200 over a real pty and streams; every value it
// delivers is checked against what the twin measured.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/hal/lms2xx/link_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;

emu::EmulatorSettings fast_emulator() {
  emu::EmulatorSettings s;
  s.scenario = default_scenario();
  s.time_scale = 0.0;  // as fast as the host reads
  return s;
}

lms::DriverSettings driver_at(unsigned baud) {
  lms::DriverSettings d;
  d.baud = baud;
  d.ack_timeout = 100ms;
  return d;
}

// Every delivered scan equals, value for value, one the device sent, in the order sent; returns
// how many sent scans were matched.
std::size_t check_delivered_against_sent(const LinkHarness& link) {
  std::size_t next = 0;
  for (std::size_t i = 0; i < link.received().size(); ++i) {
    const auto& got = link.received()[i].codes;
    while (next < link.sent().size() && link.sent()[next].codes != got) ++next;
    if (next == link.sent().size()) {
      ADD_FAILURE() << "delivered scan " << i << " matches no scan the device sent";
      return 0;
    }
    ++next;
  }
  return next;
}

class StreamingAtEachRate : public ::testing::TestWithParam<unsigned> {};

TEST_P(StreamingAtEachRate, TenThousandScansEqualTheTwinsReadings) {
  constexpr std::size_t kScans = 10000;
  LinkHarness link(fast_emulator(), driver_at(GetParam()));
  link.start();
  ASSERT_TRUE(link.wait_for_scans(kScans, 300s)) << "fewer than " << kScans << " scans arrived";
  link.stop();
  ASSERT_GE(link.received().size(), kScans);
  ASSERT_EQ(link.received().front().codes.size(), 361u);
  // No fault was injected: every scan the device sent is delivered, in order, unchanged.
  const std::size_t n = link.received().size();
  ASSERT_GE(link.sent().size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(link.received()[i].codes, link.sent()[i].codes) << "scan " << i;
  }
  const auto& c = link.driver_counters();
  EXPECT_EQ(c.decoder.crc_errors, 0u);
  EXPECT_EQ(c.rejected_scans, 0u);
  EXPECT_EQ(c.bring_ups, 1u);
  EXPECT_EQ(link.emulator_counters().bytes_lost_to_rate_mismatch, 0u);
}

INSTANTIATE_TEST_SUITE_P(Rates, StreamingAtEachRate,
                         ::testing::Values(9600u, 19200u, 38400u, 500000u));

TEST(Lms2xxLink, CentimetresAndTheQuarterDegreeVariant) {
  lms::DriverSettings d = driver_at(500000);
  d.units = lms::Units::Centimetre;
  d.variant = {100, 25};
  LinkHarness link(fast_emulator(), d);
  link.start();
  ASSERT_TRUE(link.wait_for_scans(500, 60s));
  link.stop();
  EXPECT_EQ(link.received().front().codes.size(), 401u);
  // The wall 3 m away: about 300 cm in the centre beam.
  const auto centre = link.received().front().codes[200];
  EXPECT_NEAR(centre, 300, 2);
  EXPECT_EQ(check_delivered_against_sent(link) >= link.received().size(), true);
}

TEST(Lms2xxLink, FindsTheDeviceAlreadyAtAnotherRate) {
  emu::EmulatorSettings e = fast_emulator();
  e.link =
      std::filesystem::temp_directory_path() / ("tofcomp-lms200-" + std::to_string(::getpid()));
  emu::Emulator device(e);
  device.start();
  const auto run_driver = [&](unsigned baud) {
    boost::asio::io_context io;
    lms::DriverSettings d = driver_at(baud);
    d.device = device.device_path();
    std::size_t scans = 0;
    lms::Lms2xxDriver driver(io, d, [&](const lms::HostScan&) {
      if (++scans >= 50) io.stop();  // one read may carry several more
    });
    driver.start();
    io.run_for(30s);
    return std::make_pair(scans, driver.counters());
  };
  const auto [first_scans, first] = run_driver(500000);  // device at 9600 after power-on
  EXPECT_GE(first_scans, 50u);
  EXPECT_EQ(first.rate_searches, 0u);
  const auto [second_scans, second] = run_driver(500000);  // a new host; device at 500 kBd
  EXPECT_GE(second_scans, 50u);
  EXPECT_EQ(second.rate_searches, 1u);
  EXPECT_EQ(second.device_resets, 0u);
  device.stop();
}

TEST(Lms2xxLink, TheLineRateLimitsContinuousOutputInRealTime) {
  // At 38400 Bd a 361-value scan telegram (732 bytes, 7,320 bits with start and stop bits)
  // takes 0.19 s on the line: about 5 scans/s get through
  // (shared/docs/lms2xx-protocol.md, "Link").
  emu::EmulatorSettings e = fast_emulator();
  e.time_scale = 1.0;
  LinkHarness link(e, driver_at(38400));
  link.start();
  ASSERT_TRUE(link.wait_for_scans(1, 30s));
  std::this_thread::sleep_for(3s);
  link.stop();
  const auto& r = link.received();
  const double seconds = std::chrono::duration<double>(r.back().when - r.front().when).count();
  const double rate = static_cast<double>(r.size() - 1) / seconds;
  EXPECT_GT(rate, 4.0);
  EXPECT_LT(rate, 5.6);
  // 0.5° interlaces over two mirror turns: 37.5 complete scans/s, about 32 of them skipped.
  EXPECT_GT(link.emulator_counters().scans_skipped, 80u);
  EXPECT_EQ(check_delivered_against_sent(link), link.received().size());
}

// The emulated device's supply switched off: no scan comes, however long the host waits; on
// again, the device restarts and, told the power is back, the host brings it up at once
// (reconnect_now ends its backoff), and the scans come again.
TEST(Lms2xxLink, TheEmulatedSupplySwitchStopsAndRestartsTheScans) {
  emu::EmulatorSettings settings = fast_emulator();
  settings.time_scale = 1.0;
  lms::DriverSettings driver = driver_at(500000);
  driver.scan_timeout = 300ms;
  driver.backoff_max = 10000ms;  // an unheard device would leave the host waiting long
  LinkHarness link(settings, driver);
  link.start();
  ASSERT_TRUE(link.wait_for_scans(20, 20s));
  link.emulator().set_power(false);
  EXPECT_FALSE(link.emulator().power_on());
  std::this_thread::sleep_for(200ms);  // a scan already on the line may still arrive
  const std::size_t at_off = link.received_count();
  std::this_thread::sleep_for(3s);  // the host backs off, ever longer, against a silent device
  EXPECT_EQ(link.received_count(), at_off) << "a switched-off device sent scans";
  link.emulator().set_power(true);
  EXPECT_TRUE(link.emulator().power_on());
  link.on_driver([](lms::Lms2xxDriver& d) { d.reconnect_now(); });
  const auto powered = std::chrono::steady_clock::now();
  ASSERT_TRUE(link.wait_for_scans(at_off + 20, 5s)) << "no scans after the power came back";
  EXPECT_LT(std::chrono::steady_clock::now() - powered, 3s);
  link.stop();
  EXPECT_GE(link.driver_counters().bring_ups, 2u);
}

// A device that restarts comes back at 9600 Bd with its output off, and its power-on telegram
// at that rate never reaches a host at 500 kBd: the host, finding the stream silent for a few
// scan intervals, asks at the power-on rate and brings it up again from there, long before its
// scan timeout (5 s here, so that a recovery that waited it out would show as a stream timeout).
TEST(Lms2xxLink, ARestartedDeviceIsFoundAtItsPowerOnRateWithoutAStreamTimeout) {
  emu::EmulatorSettings settings = fast_emulator();
  settings.faults.reset = 0.01;  // one telegram in a hundred
  settings.fault_seed = 56;
  lms::DriverSettings driver = driver_at(500000);
  driver.scan_timeout = 5s;
  LinkHarness link(settings, driver);
  link.start();
  constexpr std::uint64_t kResets = 8;
  const auto limit = std::chrono::steady_clock::now() + 120s;
  while (link.emulator_counters().injected.resets < kResets &&
         std::chrono::steady_clock::now() < limit) {
    std::this_thread::sleep_for(50ms);
  }
  // Until the host delivers a scan the device sent after the last reset.
  const auto last_fault = link.last_fault_time();
  const auto settle = std::chrono::steady_clock::now() + 30s;
  while (!link.delivered_scan_sent_after(last_fault) && std::chrono::steady_clock::now() < settle) {
    std::this_thread::sleep_for(50ms);
  }
  const bool recovered = link.delivered_scan_sent_after(last_fault);
  link.stop();
  // The resets the host had time to meet: those up to the last one waited for (the device goes
  // on injecting until stop()).
  const auto waited_out = static_cast<std::uint64_t>(
      std::count_if(link.faults().begin(), link.faults().end(), [&](const auto& fault) {
        return fault.first == emu::LinkFault::Reset && fault.second <= last_fault;
      }));
  const auto& host = link.driver_counters();
  ASSERT_GE(waited_out, kResets);
  EXPECT_TRUE(recovered) << "no scan after the last reset";
  EXPECT_EQ(host.stream_timeouts, 0u) << "a restart was found only by waiting out scan_timeout";
  EXPECT_GE(host.device_resets, waited_out);
  EXPECT_GE(host.restart_checks, 1u);  // a reset in the middle of a bring-up fails that instead
}

// Hang-ups with no stable link (the daemon's built-in default): each makes a new pty, and the
// host, asking at each opening which, streams again after every one.
TEST(Lms2xxLink, EachHangUpsNewPtyIsFollowed) {
  emu::EmulatorSettings settings = fast_emulator();
  settings.faults.hang_up = 0.02;  // one telegram in fifty
  settings.fault_seed = 53;
  LinkHarness link(settings, driver_at(500000));
  link.start();
  constexpr std::size_t kScans = 600;
  const bool arrived = link.wait_for_scans(kScans, 120s);
  link.stop();
  ASSERT_TRUE(arrived) << link.received().size() << " scans, "
                       << link.driver_counters().link_losses << " link losses";
  EXPECT_GE(link.emulator_counters().injected.hang_ups, 5u);
  EXPECT_GE(link.driver_counters().link_losses, 5u);
}

// A port that stops opening (the device unplugged) is backed off, doubling to backoff_max,
// however well the device answered before: with 50 ms first and 2 s at most, 2 s hold at
// most seven attempts (a retry every 50 ms would make forty).
TEST(Lms2xxLink, APortThatNoLongerOpensIsBackedOffAfterTheDeviceAnswered) {
  LinkHarness link(fast_emulator(), driver_at(500000));
  link.start();
  ASSERT_TRUE(link.wait_for_scans(20, 20s));
  link.emulator().stop();  // its pty is gone: every opening fails
  const auto gone = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(2s);
  link.stop();
  const auto backoffs_after = std::count_if(
      link.states().begin(), link.states().end(), [&](const auto& record) {
        return record.state == lms::LinkState::Backoff && record.when > gone;
      });
  EXPECT_GE(backoffs_after, 1);
  EXPECT_LE(backoffs_after, 8);
}

TEST(Lms2xxLink, ANonexistentPortBacksOffAndSaysWhy) {
  boost::asio::io_context io;
  lms::DriverSettings d = driver_at(500000);
  d.device = "/dev/tofcomp-no-such-port";
  std::vector<std::string> reasons;
  lms::Lms2xxDriver driver(
      io, d, [](const lms::HostScan&) {},
      [&](lms::LinkState s, const std::string& why) {
        if (s == lms::LinkState::Backoff) reasons.push_back(why);
      });
  driver.start();
  io.run_for(300ms);
  driver.stop();
  io.run_for(50ms);
  ASSERT_GE(reasons.size(), 2u);  // 50 ms, then 100 ms: at least two attempts in 300 ms
  EXPECT_NE(reasons.front().find("/dev/tofcomp-no-such-port"), std::string::npos)
      << reasons.front();
}

}  // namespace
}  // namespace tofcomp::test
