#include "hal/lms2xx/commands.hpp"

#include <algorithm>
#include <iterator>

namespace tofcomp::hal::lms2xx {

bool is_supported_baud(unsigned baud) {
  return std::find(std::begin(kSupportedBauds), std::end(kSupportedBauds), baud) !=
         std::end(kSupportedBauds);
}

std::optional<OperatingMode> mode_for_baud(unsigned baud) {
  switch (baud) {
    case 9600: return OperatingMode::Baud9600;
    case 19200: return OperatingMode::Baud19200;
    case 38400: return OperatingMode::Baud38400;
    case 500000: return OperatingMode::Baud500000;
    default: return std::nullopt;
  }
}

std::optional<unsigned> baud_for_mode(std::uint8_t mode) {
  switch (static_cast<OperatingMode>(mode)) {
    case OperatingMode::Baud9600: return 9600;
    case OperatingMode::Baud19200: return 19200;
    case OperatingMode::Baud38400: return 38400;
    case OperatingMode::Baud500000: return 500000;
    default: return std::nullopt;
  }
}

std::string to_string(Units units) { return units == Units::Millimetre ? "mm" : "cm"; }

bool Variant::is_valid() const {
  if (angle_deg != 100 && angle_deg != 180) return false;
  if (resolution_centideg != 25 && resolution_centideg != 50 && resolution_centideg != 100) {
    return false;
  }
  return !(resolution_centideg == 25 && angle_deg != 100);
}

std::string to_string(const Variant& variant) {
  return std::to_string(variant.angle_deg) + "° at " +
         std::to_string(variant.resolution_centideg / 100.0).substr(0, 4) + "°";
}

}  // namespace tofcomp::hal::lms2xx
