// Faults of a serial link, injected into the emulated device's output at configured rates:
// garbage bytes, a dropped byte, a corrupted CRC, a stall, a hang-up, a spontaneous reset. At
// most one fault per telegram; seeded, so a run is repeatable. Every fault is counted, so a test
// can hold the host's counters against what was done to it.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace tofcomp::sim::lms200 {

enum class LinkFault { None, Garbage, DroppedByte, CorruptedCrc, Stall, HangUp, Reset };
std::string to_string(LinkFault fault);

// Probability of each fault per telegram sent.
struct FaultRates {
  double garbage = 0.0;
  double dropped_byte = 0.0;
  double corrupted_crc = 0.0;
  double stall = 0.0;
  double hang_up = 0.0;
  double reset = 0.0;
  double stall_s = 0.5;        // how long a stall holds the output back (wall-clock seconds)
  int max_garbage_bytes = 16;  // garbage is 1..max random bytes before the telegram

  double total() const { return garbage + dropped_byte + corrupted_crc + stall + hang_up + reset; }
  // The same total split evenly over the six kinds: `per_telegram` = 0.01 is one per 100.
  static FaultRates evenly(double per_telegram);
  void validate() const;  // throws core::InvalidInput naming the rate at fault
};

struct InjectedFaults {
  std::uint64_t garbage = 0;
  std::uint64_t dropped_bytes = 0;
  std::uint64_t corrupted_crcs = 0;
  std::uint64_t stalls = 0;
  std::uint64_t hang_ups = 0;
  std::uint64_t resets = 0;
  std::uint64_t byte_faults() const { return garbage + dropped_bytes + corrupted_crcs; }
  std::uint64_t total() const { return byte_faults() + stalls + hang_ups + resets; }
  // Each kind's count under its configuration name (`emulator.faults.<name>`), in that order.
  std::vector<std::pair<std::string, std::uint64_t>> by_kind() const;
};

class FaultInjector {
 public:
  FaultInjector(FaultRates rates, std::uint64_t seed);

  // Draws this telegram's fault. Byte faults are applied to `telegram` in place; the server
  // carries out stalls, hang-ups and resets.
  LinkFault apply(std::vector<std::uint8_t>& telegram);
  const InjectedFaults& injected() const { return injected_; }
  const FaultRates& rates() const { return rates_; }

 private:
  FaultRates rates_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  InjectedFaults injected_;

  std::size_t index_below(std::size_t n);
};

}  // namespace tofcomp::sim::lms200
