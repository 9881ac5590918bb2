// The LMS 2xx telegram frame (both directions): STX, address, LEN (u16, CMD + DATA), CMD,
// DATA, CRC-16 (u16), all little-endian; and the single-byte ACK / NAK the device answers each
// request with. Facts from SICK's telegram listing, summarised in shared/docs/lms2xx-protocol.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace tofcomp::hal::lms2xx {

inline constexpr std::uint8_t kStx = 0x02;
inline constexpr std::uint8_t kAck = 0x06;
inline constexpr std::uint8_t kNak = 0x15;
// A reply's address is the device's address plus this; a reply's command, the request's plus it.
inline constexpr std::uint8_t kReplyFlag = 0x80;
// Bytes around DATA: STX, ADR, LEN (2), CMD before; CRC (2) after.
inline constexpr std::size_t kHeaderBytes = 5;
inline constexpr std::size_t kFrameOverheadBytes = kHeaderBytes + 2;
// The longest CMD + DATA a telegram carries: a 401-value scan (2 + 802 bytes of data, a scan
// index and a status byte) fits, anything longer is a corrupted length field.
inline constexpr std::size_t kMaxPayloadBytes = 1024;

struct Telegram {
  std::uint8_t address = 0;  // as on the wire: 0x80 + device address for device replies
  std::uint8_t command = 0;
  std::vector<std::uint8_t> data;  // device replies: the trailing status byte included

  bool operator==(const Telegram&) const = default;
};

// The wire bytes of a telegram, CRC included. Throws core::InvalidInput when data is too long.
std::vector<std::uint8_t> encode_telegram(const Telegram& telegram);

// Appends a little-endian u16 / reads one at `offset`.
void put_u16(std::vector<std::uint8_t>& out, std::uint16_t value);
std::uint16_t get_u16(std::span<const std::uint8_t> bytes, std::size_t offset);

}  // namespace tofcomp::hal::lms2xx
