#include "hal/lms2xx/telegram.hpp"

#include <string>

#include "core/error.hpp"
#include "hal/lms2xx/crc16.hpp"

namespace tofcomp::hal::lms2xx {

void put_u16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value & 0xff));
  out.push_back(static_cast<std::uint8_t>(value >> 8));
}

std::uint16_t get_u16(std::span<const std::uint8_t> bytes, std::size_t offset) {
  if (offset + 2 > bytes.size()) {
    throw core::InvalidInput("telegram: a u16 at byte " + std::to_string(offset) +
                             " lies beyond the " + std::to_string(bytes.size()) + " bytes of data");
  }
  return static_cast<std::uint16_t>(bytes[offset] | (bytes[offset + 1] << 8));
}

std::vector<std::uint8_t> encode_telegram(const Telegram& telegram) {
  const std::size_t payload = telegram.data.size() + 1;
  if (payload > kMaxPayloadBytes) {
    throw core::InvalidInput("telegram: " + std::to_string(payload) +
                             " bytes of command and data exceed the limit of " +
                             std::to_string(kMaxPayloadBytes));
  }
  std::vector<std::uint8_t> out;
  out.reserve(payload + kFrameOverheadBytes);
  out.push_back(kStx);
  out.push_back(telegram.address);
  put_u16(out, static_cast<std::uint16_t>(payload));
  out.push_back(telegram.command);
  out.insert(out.end(), telegram.data.begin(), telegram.data.end());
  put_u16(out, sick_crc16(out));
  return out;
}

}  // namespace tofcomp::hal::lms2xx
