#include "hal/lms2xx/measuring_mode.hpp"

namespace tofcomp::hal::lms2xx {

namespace {
std::uint16_t all_ones(MeasuringMode mode) {
  return static_cast<std::uint16_t>((1u << distance_bits(mode)) - 1u);
}
}  // namespace

std::optional<MeasuringMode> measuring_mode_from_byte(std::uint8_t byte) {
  switch (byte) {
    case 0x00: return MeasuringMode::Range8m;
    case 0x05: return MeasuringMode::Range16m;
    case 0x06: return MeasuringMode::Range32m;
    default: return std::nullopt;
  }
}

int distance_bits(MeasuringMode mode) {
  switch (mode) {
    case MeasuringMode::Range16m: return 14;
    case MeasuringMode::Range32m: return 15;
    case MeasuringMode::Range8m: break;
  }
  return 13;
}

std::string to_string(ValueStatus status) {
  switch (status) {
    case ValueStatus::Distance: return "distance";
    case ValueStatus::BeyondMaximum: return "no echo within range";
    case ValueStatus::SignalTooSmall: return "signal too small";
    case ValueStatus::Overflow: return "operation overflow";
    case ValueStatus::Dazzled: return "dazzled";
    case ValueStatus::NotValid: return "not valid";
    case ValueStatus::Reserved: return "reserved code";
  }
  return "unknown";
}

std::uint16_t max_distance_code(MeasuringMode mode) {
  return static_cast<std::uint16_t>(all_ones(mode) - 9);
}

ValueStatus classify_distance_code(MeasuringMode mode, std::uint16_t code) {
  const std::uint16_t top = all_ones(mode);
  if (code <= max_distance_code(mode)) return ValueStatus::Distance;
  switch (top - code) {
    case 8: return ValueStatus::BeyondMaximum;
    case 4: return ValueStatus::SignalTooSmall;
    case 2: return ValueStatus::Overflow;
    case 1: return ValueStatus::Dazzled;
    case 0: return ValueStatus::NotValid;
    default: return ValueStatus::Reserved;
  }
}

std::uint16_t code_for_status(MeasuringMode mode, ValueStatus status) {
  const std::uint16_t top = all_ones(mode);
  switch (status) {
    case ValueStatus::BeyondMaximum: return static_cast<std::uint16_t>(top - 8);
    case ValueStatus::SignalTooSmall: return static_cast<std::uint16_t>(top - 4);
    case ValueStatus::Overflow: return static_cast<std::uint16_t>(top - 2);
    case ValueStatus::Dazzled: return static_cast<std::uint16_t>(top - 1);
    case ValueStatus::NotValid:
    case ValueStatus::Reserved:
    case ValueStatus::Distance: break;
  }
  return top;
}

}  // namespace tofcomp::hal::lms2xx
