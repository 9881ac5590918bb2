#include "hal/lms2xx/messages.hpp"

#include <cstring>

#include "core/error.hpp"

namespace tofcomp::hal::lms2xx {

namespace {

Telegram request(Command command, std::vector<std::uint8_t> data = {}) {
  return Telegram{kDefaultDeviceAddress, static_cast<std::uint8_t>(command), std::move(data)};
}

std::string hex(std::uint8_t byte) {
  static const char* digits = "0123456789ABCDEF";
  return std::string("0x") + digits[byte >> 4] + digits[byte & 0xf];
}

}  // namespace

Telegram reset_request() { return request(Command::Reset); }

Telegram switch_mode_request(OperatingMode mode) {
  return request(Command::SwitchMode, {static_cast<std::uint8_t>(mode)});
}

Telegram installation_mode_request() {
  std::vector<std::uint8_t> data{static_cast<std::uint8_t>(OperatingMode::Installation)};
  data.insert(data.end(), kInstallationPassword,
              kInstallationPassword + std::strlen(kInstallationPassword));
  return request(Command::SwitchMode, std::move(data));
}

Telegram values_request() { return request(Command::RequestValues, {0x01}); }
Telegram status_request() { return request(Command::Status); }
Telegram error_test_request() { return request(Command::ErrorTest); }
Telegram type_request() { return request(Command::Type); }

Telegram variant_request(const Variant& variant) {
  std::vector<std::uint8_t> data;
  put_u16(data, variant.angle_deg);
  put_u16(data, variant.resolution_centideg);
  return request(Command::Variant, std::move(data));
}

Telegram configuration_request() { return request(Command::RequestConfiguration); }

Telegram configure_request(const ConfigurationBlock& block) {
  const auto bytes = block.bytes();
  return request(Command::Configure, std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
}

Telegram make_reply(std::uint8_t reply_code, std::span<const std::uint8_t> data,
                    std::uint8_t status, std::uint8_t device_address) {
  Telegram reply{static_cast<std::uint8_t>(kReplyFlag | device_address), reply_code,
                 std::vector<std::uint8_t>(data.begin(), data.end())};
  reply.data.push_back(status);
  return reply;
}

std::span<const std::uint8_t> reply_body(const Telegram& reply, std::uint8_t expected_code,
                                         std::size_t min_bytes) {
  if (reply.command != expected_code) {
    throw core::InvalidInput("reply " + hex(reply.command) + " where " + hex(expected_code) +
                             " was expected");
  }
  if (reply.data.size() < min_bytes + 1) {
    throw core::InvalidInput("reply " + hex(reply.command) + ": " +
                             std::to_string(reply.data.size()) + " bytes of data, expected at least " +
                             std::to_string(min_bytes + 1) + " (with the status byte)");
  }
  return std::span<const std::uint8_t>(reply.data).first(reply.data.size() - 1);
}

ModeSwitchResult parse_mode_switch_reply(const Telegram& reply) {
  const auto body = reply_body(reply, reply_code(Command::SwitchMode), 1);
  if (body[0] > 2) {
    throw core::InvalidInput("reply 0xA0: result code " + std::to_string(body[0]) +
                             " is none of 0 (success), 1 (wrong password), 2 (failed)");
  }
  return static_cast<ModeSwitchResult>(body[0]);
}

VariantReply parse_variant_reply(const Telegram& reply) {
  const auto body = reply_body(reply, reply_code(Command::Variant), 5);
  VariantReply out;
  out.accepted = body[0] == 0x01;
  out.active.angle_deg = get_u16(body, 1);
  out.active.resolution_centideg = get_u16(body, 3);
  return out;
}

std::string parse_type_reply(const Telegram& reply) {
  const auto body = reply_body(reply, reply_code(Command::Type), 1);
  std::string type(body.begin(), body.end());
  while (!type.empty() && (type.back() == ' ' || type.back() == '\0')) type.pop_back();
  return type;
}

ConfigurationBlock parse_configuration_reply(const Telegram& reply) {
  return ConfigurationBlock::parse(
      reply_body(reply, reply_code(Command::RequestConfiguration), ConfigurationBlock::kBytes)
          .first(ConfigurationBlock::kBytes));
}

ConfigureReply parse_configure_reply(const Telegram& reply) {
  const auto body =
      reply_body(reply, reply_code(Command::Configure), 1 + ConfigurationBlock::kBytes);
  return ConfigureReply{body[0] == 0x01,
                        ConfigurationBlock::parse(body.subspan(1, ConfigurationBlock::kBytes))};
}

StatusReply parse_status_reply(const Telegram& reply) {
  const auto body = reply_body(reply, reply_code(Command::Status), kStatusBytes);
  StatusReply out;
  out.firmware_version.assign(body.begin(), body.begin() + 7);
  out.operating_mode = body[7];
  out.device_status = body[8];
  return out;
}

}  // namespace tofcomp::hal::lms2xx
