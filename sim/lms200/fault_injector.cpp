#include "sim/lms200/fault_injector.hpp"

#include "core/error.hpp"

namespace tofcomp::sim::lms200 {

std::string to_string(LinkFault fault) {
  switch (fault) {
    case LinkFault::None:
      return "none";
    case LinkFault::Garbage:
      return "garbage";
    case LinkFault::DroppedByte:
      return "dropped byte";
    case LinkFault::CorruptedCrc:
      return "corrupted CRC";
    case LinkFault::Stall:
      return "stall";
    case LinkFault::HangUp:
      return "hang-up";
    case LinkFault::Reset:
      return "reset";
  }
  return "unknown";
}

FaultRates FaultRates::evenly(double per_telegram) {
  FaultRates r;
  const double each = per_telegram / 6.0;
  r.garbage = r.dropped_byte = r.corrupted_crc = r.stall = r.hang_up = r.reset = each;
  return r;
}

void FaultRates::validate() const {
  const std::pair<const char*, double> rates[] = {
      {"garbage", garbage}, {"dropped_byte", dropped_byte}, {"corrupted_crc", corrupted_crc},
      {"stall", stall},     {"hang_up", hang_up},           {"reset", reset}};
  for (const auto& [name, value] : rates) {
    if (!(value >= 0.0 && value <= 1.0)) {
      throw core::InvalidInput(std::string("fault rate ") + name + " = " + std::to_string(value) +
                               ": must be a probability per telegram in [0, 1]");
    }
  }
  if (total() > 1.0) {
    throw core::InvalidInput("fault rates add up to " + std::to_string(total()) +
                             " per telegram: at most 1");
  }
  if (!(stall_s > 0.0) || max_garbage_bytes < 1) {
    throw core::InvalidInput("fault stall_s must be positive and max_garbage_bytes at least 1");
  }
}

std::vector<std::pair<std::string, std::uint64_t>> InjectedFaults::by_kind() const {
  return {{"garbage", garbage}, {"dropped_byte", dropped_bytes}, {"corrupted_crc", corrupted_crcs},
          {"stall", stalls},     {"hang_up", hang_ups},           {"reset", resets}};
}

FaultInjector::FaultInjector(FaultRates rates, std::uint64_t seed) : rates_(rates), rng_(seed) {
  rates_.validate();
}

std::size_t FaultInjector::index_below(std::size_t n) {
  return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
}

LinkFault FaultInjector::apply(std::vector<std::uint8_t>& telegram) {
  if (rates_.total() <= 0.0 || telegram.empty()) return LinkFault::None;
  double u = uniform_(rng_);
  const auto hit = [&u](double rate) {
    if (u < rate) return true;
    u -= rate;
    return false;
  };
  if (hit(rates_.garbage)) {
    ++injected_.garbage;
    const std::size_t n = 1 + index_below(static_cast<std::size_t>(rates_.max_garbage_bytes));
    std::vector<std::uint8_t> noise(n);
    for (auto& b : noise) b = static_cast<std::uint8_t>(index_below(256));
    telegram.insert(telegram.begin(), noise.begin(), noise.end());
    return LinkFault::Garbage;
  }
  if (hit(rates_.dropped_byte)) {
    ++injected_.dropped_bytes;
    telegram.erase(telegram.begin() + static_cast<std::ptrdiff_t>(index_below(telegram.size())));
    return LinkFault::DroppedByte;
  }
  if (hit(rates_.corrupted_crc)) {
    ++injected_.corrupted_crcs;
    telegram.back() ^= static_cast<std::uint8_t>(1 + index_below(255));
    return LinkFault::CorruptedCrc;
  }
  if (hit(rates_.stall)) {
    ++injected_.stalls;
    return LinkFault::Stall;
  }
  if (hit(rates_.hang_up)) {
    ++injected_.hang_ups;
    return LinkFault::HangUp;
  }
  if (hit(rates_.reset)) {
    ++injected_.resets;
    return LinkFault::Reset;
  }
  return LinkFault::None;
}

}  // namespace tofcomp::sim::lms200
