// 100,000 telegrams with one fault in a hundred (garbage, dropped bytes, corrupted CRCs,
// stalls, hang-ups and resets, in equal shares): the host driver accepts no corrupted scan,
// counts every fault it can see, and is streaming again within 1 s of each hang-up or reset.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/hal/lms2xx/link_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST(Lms2xxLinkUnderFaults, OneFaultPerHundredTelegrams) {
  constexpr std::uint64_t kTelegrams = 100000;
  emu::EmulatorSettings e;
  e.scenario = default_scenario();
  e.time_scale = 0.0;
  e.faults = emu::FaultRates::evenly(0.01);
  e.faults.stall_s = 0.3;
  e.fault_seed = 2015;
  e.link = std::filesystem::temp_directory_path() /
           ("tofcomp-lms200-faults-" + std::to_string(::getpid()));
  lms::DriverSettings d;
  d.baud = 500000;
  d.variant = {180, 100};  // 181 values: shorter telegrams, more of them per second
  d.ack_timeout = 100ms;
  d.scan_timeout = 200ms;  // shorter than a stall, so each stall is noticed
  LinkHarness link(e, d);
  link.start();
  const auto limit = Clock::now() + 600s;
  while (link.emulator_counters().telegrams_sent < kTelegrams && Clock::now() < limit) {
    std::this_thread::sleep_for(100ms);
  }
  // The last fault's recovery: until the host delivers a scan the device sent after it (or 10 s,
  // and the check below fails). Not merely one received after it: the scan the device wrote just
  // before a reset is often read by the host just after it, and the host, stopped then, would
  // have had no time to see the reset (the device is silent while it restarts, and the host at
  // another rate learns of it only when the stream times out).
  const auto last_fault = link.last_fault_time();
  const auto settle = Clock::now() + 10s;
  while (!link.delivered_scan_sent_after(last_fault) && Clock::now() < settle) {
    std::this_thread::sleep_for(50ms);
  }
  link.stop();

  const auto injected = link.emulator_counters().injected;
  const auto& host = link.driver_counters();
  ASSERT_GE(link.emulator_counters().telegrams_sent, kTelegrams);
  // About one in a hundred telegrams was faulted.
  EXPECT_GT(injected.total(), 800u);
  EXPECT_LT(injected.total(), 1200u);

  // No corrupted scan accepted: every delivered scan is one the device sent, in order.
  std::vector<Clock::time_point> sent_at;  // when the device sent each delivered scan
  std::size_t next = 0;
  for (std::size_t i = 0; i < link.received().size(); ++i) {
    while (next < link.sent().size() && link.sent()[next].codes != link.received()[i].codes) {
      ++next;
    }
    ASSERT_LT(next, link.sent().size()) << "delivered scan " << i << " was never sent";
    sent_at.push_back(link.sent()[next].when);
    ASSERT_EQ(link.sent()[next].fault == emu::LinkFault::DroppedByte ||
                  link.sent()[next].fault == emu::LinkFault::CorruptedCrc,
              false)
        << "delivered scan " << i << " was damaged on the line";
    ++next;
  }

  // Every fault is counted: byte faults by the decoder, stalls as stream timeouts (or as the
  // reset the host then finds), resets as device resets, hang-ups as link losses. Bytes the
  // device writes while the host has the port closed wait in the pty for the host's next open,
  // so only a hang-up can pass unseen: one that comes while the host has no port open (backing
  // off after a failed bring-up) reaches no one, and is not asked for. A hang-up is a link
  // loss however the host meets it: the host's thread is often between its last read and its
  // next request when the line drops (more often on a loaded machine), and then the request's
  // write fails before the reader hears of it (3 of 171 in one run); a driver that counted only
  // the reader's losses made this check fail now and then under load (170 of 171). So did a
  // hang-up in the instant before the driver closed the port for another reason (170 of 171
  // again, under a full ctest): the reader's failed read was still queued and the close replaced
  // the reader; the driver now asks the port itself whether it hung up as it closes it.
  // The device goes on injecting faults until stop(): one injected after the settle wait's
  // snapshot may have had no time to be seen, so the counts compared are those up to it.
  std::uint64_t unheard_hang_ups = 0;
  emu::InjectedFaults waited_out;
  for (const auto& [fault, when] : link.faults()) {
    if (fault == emu::LinkFault::HangUp && !link.host_listening_at(when)) ++unheard_hang_ups;
    if (when > last_fault) continue;
    switch (fault) {
      case emu::LinkFault::Garbage: ++waited_out.garbage; break;
      case emu::LinkFault::DroppedByte: ++waited_out.dropped_bytes; break;
      case emu::LinkFault::CorruptedCrc: ++waited_out.corrupted_crcs; break;
      case emu::LinkFault::Stall: ++waited_out.stalls; break;
      case emu::LinkFault::HangUp: ++waited_out.hang_ups; break;
      case emu::LinkFault::Reset: ++waited_out.resets; break;
      case emu::LinkFault::None: break;
    }
  }
  std::printf(
      "injected: garbage %lu dropped %lu crc %lu stalls %lu hang-ups %lu (%lu while the "
      "host had the port closed) resets %lu\n",
      injected.garbage, injected.dropped_bytes, injected.corrupted_crcs, injected.stalls,
      injected.hang_ups, unheard_hang_ups, injected.resets);
  std::printf(
      "host: faults %lu (runs %lu crc %lu len %lu trunc %lu) stream timeouts %lu link "
      "losses %lu device resets %lu bring-ups %lu scans %lu of %zu sent\n",
      host.decoder.faults(), host.decoder.garbage_runs, host.decoder.crc_errors,
      host.decoder.length_errors, host.decoder.truncated, host.stream_timeouts, host.link_losses,
      host.device_resets, host.bring_ups, host.scans, link.sent().size());
  EXPECT_GE(host.decoder.faults(), waited_out.byte_faults());
  EXPECT_GE(host.stream_timeouts + host.device_resets, waited_out.stalls);
  EXPECT_GE(host.device_resets, waited_out.resets);
  EXPECT_GE(host.link_losses + unheard_hang_ups, waited_out.hang_ups);
  EXPECT_LT(unheard_hang_ups, injected.hang_ups / 10) << "the host was closed for too many";

  // Streaming again after each hang-up and reset the test waited out (the device goes on
  // injecting faults until stop(), and one in the last moments before it has no scan after it),
  // within the driver's own bound: a failed bring-up (its acknowledgements timing out) and the
  // longest backoff. A bound from the settings, not from this machine's speed: under load a
  // recovery here took up to 1.1 s of the 0.6 s it takes idle. The first scan after the fault is
  // the first delivered that the device sent after it, as in the settle wait above.
  const Clock::duration recovery_bound = d.backoff_max + 10 * d.ack_timeout;
  Clock::duration slowest{};
  for (const auto& [fault, when] : link.faults()) {
    if (fault != emu::LinkFault::HangUp && fault != emu::LinkFault::Reset) continue;
    if (when > last_fault) continue;
    const auto first = std::find_if(sent_at.begin(), sent_at.end(),
                                    [&](Clock::time_point sent) { return sent > when; });
    ASSERT_NE(first, sent_at.end()) << "no scan after a " << emu::to_string(fault);
    const auto after = link.received().begin() + (first - sent_at.begin());
    slowest = std::max(slowest, after->when - when);
    EXPECT_LT(after->when - when, recovery_bound)
        << "streaming resumed " << std::chrono::duration<double>(after->when - when).count()
        << " s after a " << emu::to_string(fault);
  }
  std::printf("slowest recovery after a hang-up or reset: %.3f s\n",
              std::chrono::duration<double>(slowest).count());
}

}  // namespace
}  // namespace tofcomp::test
