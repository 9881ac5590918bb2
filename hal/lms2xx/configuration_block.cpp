#include "hal/lms2xx/configuration_block.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace tofcomp::hal::lms2xx {

ConfigurationBlock::ConfigurationBlock() {
  set_measuring_mode(MeasuringMode::Range8m);
  set_units(Units::Millimetre);
}

ConfigurationBlock ConfigurationBlock::parse(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kBytes) {
    throw core::InvalidInput("configuration block: " + std::to_string(bytes.size()) +
                             " bytes, expected " + std::to_string(kBytes));
  }
  ConfigurationBlock block;
  std::copy(bytes.begin(), bytes.end(), block.bytes_.begin());
  if (!measuring_mode_from_byte(block.bytes_[kMeasuringModeOffset])) {
    throw core::InvalidInput("configuration block: byte " + std::to_string(kMeasuringModeOffset) +
                             " (measuring mode) holds unknown code " +
                             std::to_string(block.bytes_[kMeasuringModeOffset]));
  }
  if (block.bytes_[kUnitsOffset] > 1) {
    throw core::InvalidInput("configuration block: byte " + std::to_string(kUnitsOffset) +
                             " (units) holds " + std::to_string(block.bytes_[kUnitsOffset]) +
                             ", expected 0 (cm) or 1 (mm)");
  }
  return block;
}

MeasuringMode ConfigurationBlock::measuring_mode() const {
  return *measuring_mode_from_byte(bytes_[kMeasuringModeOffset]);
}

Units ConfigurationBlock::units() const { return static_cast<Units>(bytes_[kUnitsOffset]); }

void ConfigurationBlock::set_measuring_mode(MeasuringMode mode) {
  bytes_[kMeasuringModeOffset] = static_cast<std::uint8_t>(mode);
}

void ConfigurationBlock::set_units(Units units) {
  bytes_[kUnitsOffset] = static_cast<std::uint8_t>(units);
}

}  // namespace tofcomp::hal::lms2xx
