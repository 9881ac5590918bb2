#include "hal/lms2xx/crc16.hpp"

namespace tofcomp::hal::lms2xx {

std::uint16_t sick_crc16(std::span<const std::uint8_t> bytes) {
  constexpr std::uint16_t kPolynomial = 0x8005;
  std::uint16_t crc = 0;
  std::uint16_t previous = 0;
  for (const std::uint8_t byte : bytes) {
    const std::uint16_t pair = static_cast<std::uint16_t>(byte | (previous << 8));
    previous = byte;
    if (crc & 0x8000) {
      crc = static_cast<std::uint16_t>(((crc & 0x7fff) << 1) ^ kPolynomial);
    } else {
      crc = static_cast<std::uint16_t>(crc << 1);
    }
    crc ^= pair;
  }
  return crc;
}

}  // namespace tofcomp::hal::lms2xx
