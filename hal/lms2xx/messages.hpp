// The requests a host sends and the replies the device answers with (shared/docs/
// lms2xx-protocol.md, "Commands host drivers use"): builders for each request, and parsers that
// check each reply's code and length and name what is wrong.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/configuration_block.hpp"
#include "hal/lms2xx/telegram.hpp"

namespace tofcomp::hal::lms2xx {

inline constexpr std::uint8_t kDefaultDeviceAddress = 0x00;

// ---- requests (host to device) ----
Telegram reset_request();
Telegram switch_mode_request(OperatingMode mode);
Telegram installation_mode_request();  // SwitchMode 0x00 with the password
Telegram values_request();              // 0x30 0x01: all values of one scan
Telegram status_request();
Telegram error_test_request();
Telegram type_request();
Telegram variant_request(const Variant& variant);
Telegram configuration_request();
Telegram configure_request(const ConfigurationBlock& block);

// ---- replies (device to host) ----
// A device telegram: code, data, and the status byte that ends every reply.
Telegram make_reply(std::uint8_t reply_code, std::span<const std::uint8_t> data,
                    std::uint8_t status, std::uint8_t device_address = kDefaultDeviceAddress);
// The reply's data without the trailing status byte. Throws core::InvalidInput when the
// telegram's code is not `expected_code` or it is shorter than `min_bytes` + status.
std::span<const std::uint8_t> reply_body(const Telegram& reply, std::uint8_t expected_code,
                                         std::size_t min_bytes);

ModeSwitchResult parse_mode_switch_reply(const Telegram& reply);

struct VariantReply {
  bool accepted = false;
  Variant active;
};
VariantReply parse_variant_reply(const Telegram& reply);

std::string parse_type_reply(const Telegram& reply);
ConfigurationBlock parse_configuration_reply(const Telegram& reply);

struct ConfigureReply {
  bool accepted = false;
  ConfigurationBlock stored;
};
ConfigureReply parse_configure_reply(const Telegram& reply);

// The status block (0xB1) is kStatusBytes long; the codec reads the firmware version (bytes 0-6),
// the operating mode (7) and the device status (8, 0 = no error) and carries the rest.
inline constexpr std::size_t kStatusBytes = 152;
struct StatusReply {
  std::string firmware_version;
  std::uint8_t operating_mode = 0;
  std::uint8_t device_status = 0;
};
StatusReply parse_status_reply(const Telegram& reply);

}  // namespace tofcomp::hal::lms2xx
