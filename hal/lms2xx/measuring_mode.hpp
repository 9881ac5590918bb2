// How a scan value's 16 bits divide into distance and flags, by the configuration's measuring
// mode, and the reserved distance codes at the top of the distance range (the listing's
// section on the measured-value format; marked *verify* in shared/docs/lms2xx-protocol.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace tofcomp::hal::lms2xx {

// Measuring modes of the configuration block: the range and how many bits carry distance.
enum class MeasuringMode : std::uint8_t {
  Range8m = 0x00,   // 8 m in mm (80 m in cm): 13 distance bits, flags field A, field B, dazzle
  Range16m = 0x05,  // 16 m in mm: 14 distance bits
  Range32m = 0x06,  // 32 m in mm: 15 distance bits
};
std::optional<MeasuringMode> measuring_mode_from_byte(std::uint8_t byte);
int distance_bits(MeasuringMode mode);

// What a scan value says when it is not a distance.
enum class ValueStatus : std::uint8_t {
  Distance,        // a measured distance
  BeyondMaximum,   // no echo within the range (max - 8)
  SignalTooSmall,  // signal-to-noise too small (max - 4)
  Overflow,        // operation overflow (max - 2)
  Dazzled,         // dazzling (max - 1)
  NotValid,        // no valid measurement (max)
  Reserved,        // another code of the reserved block
};
std::string to_string(ValueStatus status);

// The largest distance code that is a distance; codes above are reserved.
std::uint16_t max_distance_code(MeasuringMode mode);
ValueStatus classify_distance_code(MeasuringMode mode, std::uint16_t code);
std::uint16_t code_for_status(MeasuringMode mode, ValueStatus status);

}  // namespace tofcomp::hal::lms2xx
