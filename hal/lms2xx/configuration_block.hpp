// The configuration block of requests 0x74 (read) and 0x77 (write): 32 bytes as the LMS 200
// stores them. The codec interprets the fields a compensating host must control, the measuring
// mode and the units, and carries the rest (blanking, thresholds, availability, fields,
// restart, contours) unchanged. Offsets from the listing's configuration table (*verify*).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/measuring_mode.hpp"

namespace tofcomp::hal::lms2xx {

class ConfigurationBlock {
 public:
  static constexpr std::size_t kBytes = 32;
  static constexpr std::size_t kMeasuringModeOffset = 5;
  static constexpr std::size_t kUnitsOffset = 6;

  // The factory configuration: 8 m mode in millimetres, everything else zero.
  ConfigurationBlock();
  // Throws core::InvalidInput when bytes is not kBytes long or a field holds an unknown code.
  static ConfigurationBlock parse(std::span<const std::uint8_t> bytes);

  MeasuringMode measuring_mode() const;
  Units units() const;
  void set_measuring_mode(MeasuringMode mode);
  void set_units(Units units);

  std::span<const std::uint8_t> bytes() const { return bytes_; }
  bool operator==(const ConfigurationBlock&) const = default;

 private:
  std::array<std::uint8_t, kBytes> bytes_{};
};

}  // namespace tofcomp::hal::lms2xx
