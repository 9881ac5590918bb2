// Command codes, operating modes, baud rates and scan variants of the LMS 2xx telegram listing
// (shared/docs/lms2xx-protocol.md, "Commands host drivers use").
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace tofcomp::hal::lms2xx {

// Requests (host to device). A reply's code is the request's plus 0x80.
enum class Command : std::uint8_t {
  Reset = 0x10,
  SwitchMode = 0x20,
  RequestValues = 0x30,
  Status = 0x31,
  ErrorTest = 0x32,
  Type = 0x3A,
  Variant = 0x3B,
  RequestConfiguration = 0x74,
  Configure = 0x77,
};

// Device telegrams that answer no request of the same code.
inline constexpr std::uint8_t kPowerOnReply = 0x91;  // after a reset or power-on
inline constexpr std::uint8_t kScanReply = 0xB0;     // measured values, requested or streamed

constexpr std::uint8_t reply_code(Command request) {
  return static_cast<std::uint8_t>(static_cast<std::uint8_t>(request) | 0x80);
}

// The argument of SwitchMode (0x20).
enum class OperatingMode : std::uint8_t {
  Installation = 0x00,  // followed by the password; configuration is allowed only here
  ContinuousAll = 0x24,  // every value of every scan, streamed
  OnRequest = 0x25,      // values only when asked (ends continuous output)
  MeanValues = 0x26,
  Baud38400 = 0x40,
  Baud19200 = 0x41,
  Baud9600 = 0x42,
  Baud500000 = 0x48,
};

inline constexpr char kInstallationPassword[] = "SICK_LMS";  // 8 bytes, no terminator sent

// Result byte of the mode-switch reply 0xA0.
enum class ModeSwitchResult : std::uint8_t { Success = 0x00, WrongPassword = 0x01, Failed = 0x02 };

// The rates of the listing; 9600 Bd after power-on and after a reset.
inline constexpr unsigned kPowerOnBaud = 9600;
inline constexpr unsigned kSupportedBauds[] = {9600, 19200, 38400, 500000};
bool is_supported_baud(unsigned baud);
// The SwitchMode argument that selects `baud`; empty for a rate the device does not have.
std::optional<OperatingMode> mode_for_baud(unsigned baud);
// The rate a SwitchMode argument selects; empty when the argument is not a rate change.
std::optional<unsigned> baud_for_mode(std::uint8_t mode);

// Range units of the configuration and of the scan telegram's header (bits 14-15).
enum class Units : std::uint8_t { Centimetre = 0x00, Millimetre = 0x01 };
std::string to_string(Units units);

// The scan variant (0x3B): field of view and angular resolution.
struct Variant {
  std::uint16_t angle_deg = 180;               // 100 or 180
  std::uint16_t resolution_centideg = 50;      // 25, 50 or 100 (hundredths of a degree)

  bool is_valid() const;  // 0.25° only with the 100° field
  int values_per_scan() const { return angle_deg * 100 / resolution_centideg + 1; }
  // Mirror turns per complete scan: 0.5° and 0.25° interlace over 2 and 4 turns.
  int turns_per_scan() const { return 100 / resolution_centideg; }
  bool operator==(const Variant&) const = default;
};
std::string to_string(const Variant& variant);

}  // namespace tofcomp::hal::lms2xx
