#include "sim/lms200/device.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "hal/lms2xx/messages.hpp"

namespace tofcomp::sim::lms200 {

using protocol::Command;
using protocol::ModeSwitchResult;
using protocol::OperatingMode;

namespace {

DeviceOutput send(std::vector<std::uint8_t> bytes) {
  return DeviceOutput{DeviceOutput::Action::Send, std::move(bytes), 0};
}

// The request lengths (bytes of data after CMD) the listing defines; others are NAKed.
bool length_is_valid(Command command, std::size_t data_bytes) {
  switch (command) {
    case Command::Reset:
    case Command::Status:
    case Command::ErrorTest:
    case Command::Type:
    case Command::RequestConfiguration:
      return data_bytes == 0;
    case Command::RequestValues:
      return data_bytes == 1;
    case Command::SwitchMode:
      return data_bytes == 1 || data_bytes == 9;
    case Command::Variant:
      return data_bytes == 4;
    case Command::Configure:
      return data_bytes == protocol::ConfigurationBlock::kBytes;
  }
  return false;
}

bool is_known(std::uint8_t code) {
  switch (static_cast<Command>(code)) {
    case Command::Reset:
    case Command::SwitchMode:
    case Command::RequestValues:
    case Command::Status:
    case Command::ErrorTest:
    case Command::Type:
    case Command::Variant:
    case Command::RequestConfiguration:
    case Command::Configure:
      return true;
  }
  return false;
}

}  // namespace

Lms200Device::Lms200Device(DeviceIdentity identity) : identity_(std::move(identity)) {}

void Lms200Device::restart() {
  baud_ = protocol::kPowerOnBaud;
  streaming_ = false;
  installation_mode_ = false;
  variant_ = protocol::Variant{};
  configuration_ = protocol::ConfigurationBlock{};
  decoder_.reset();
}

std::vector<std::uint8_t> Lms200Device::power_on_telegram() const {
  const std::string text = identity_.type + " " + identity_.firmware_version;
  const std::vector<std::uint8_t> data(text.begin(), text.end());
  return protocol::encode_telegram(
      protocol::make_reply(protocol::kPowerOnReply, data, status_byte_));
}

void Lms200Device::receive(std::span<const std::uint8_t> bytes, std::vector<DeviceOutput>& out) {
  // A frame that fails its CRC or length check is rejected with a NAK, as the device does.
  const auto rejected = [this] {
    return decoder_.counters().crc_errors + decoder_.counters().length_errors;
  };
  std::uint64_t seen = rejected();
  decoder_.feed(bytes, [&](const protocol::DecoderEvent& event) {
    for (; seen < rejected(); ++seen) nak(out);
    if (event.kind == protocol::DecoderEvent::Kind::Telegram) answer(*event.telegram, out);
  });
  for (; seen < rejected(); ++seen) nak(out);
}

void Lms200Device::nak(std::vector<DeviceOutput>& out) {
  ++naks_sent_;
  out.push_back(send({protocol::kNak}));
}

void Lms200Device::reply(std::uint8_t code, std::span<const std::uint8_t> data,
                         std::vector<DeviceOutput>& out) const {
  std::vector<std::uint8_t> bytes{protocol::kAck};
  const auto telegram = protocol::encode_telegram(protocol::make_reply(code, data, status_byte_));
  bytes.insert(bytes.end(), telegram.begin(), telegram.end());
  out.push_back(send(std::move(bytes)));
}

void Lms200Device::answer(const protocol::Telegram& request, std::vector<DeviceOutput>& out) {
  if (request.address != protocol::kDefaultDeviceAddress || !is_known(request.command)) {
    nak(out);
    return;
  }
  const auto command = static_cast<Command>(request.command);
  if (!length_is_valid(command, request.data.size())) {
    nak(out);
    return;
  }
  const std::uint8_t code = protocol::reply_code(command);
  switch (command) {
    case Command::Reset:
      out.push_back(send({protocol::kAck}));
      out.push_back(DeviceOutput{DeviceOutput::Action::Restart, {}, 0});
      return;
    case Command::SwitchMode:
      switch_mode(request.data, out);
      return;
    case Command::RequestValues:
      if (request.data[0] != 0x01) {
        nak(out);
        return;
      }
      // The server answers with a fresh scan: the ACK now, the 0xB0 telegram from the twin.
      out.push_back(send({protocol::kAck}));
      out.push_back(DeviceOutput{DeviceOutput::Action::SendScan, {}, 0});
      return;
    case Command::Status: {
      const auto block = status_block();
      reply(code, block, out);
      return;
    }
    case Command::ErrorTest:
      reply(code, {}, out);
      return;
    case Command::Type: {
      const std::vector<std::uint8_t> text(identity_.type.begin(), identity_.type.end());
      reply(code, text, out);
      return;
    }
    case Command::Variant: {
      const protocol::Variant wanted{protocol::get_u16(request.data, 0),
                                     protocol::get_u16(request.data, 2)};
      const bool accepted = wanted.is_valid();
      if (accepted) variant_ = wanted;
      std::vector<std::uint8_t> data{static_cast<std::uint8_t>(accepted ? 0x01 : 0x00)};
      protocol::put_u16(data, variant_.angle_deg);
      protocol::put_u16(data, variant_.resolution_centideg);
      reply(code, data, out);
      return;
    }
    case Command::RequestConfiguration:
      reply(code, configuration_.bytes(), out);
      return;
    case Command::Configure: {
      bool accepted = installation_mode_;
      if (accepted) {
        try {
          configuration_ = protocol::ConfigurationBlock::parse(request.data);
        } catch (const core::InvalidInput&) {
          accepted = false;
        }
      }
      std::vector<std::uint8_t> data{static_cast<std::uint8_t>(accepted ? 0x01 : 0x00)};
      const auto stored = configuration_.bytes();
      data.insert(data.end(), stored.begin(), stored.end());
      reply(code, data, out);
      return;
    }
  }
}

void Lms200Device::switch_mode(std::span<const std::uint8_t> data, std::vector<DeviceOutput>& out) {
  const std::uint8_t code = protocol::reply_code(Command::SwitchMode);
  const auto result = [&](ModeSwitchResult r) {
    const std::uint8_t byte = static_cast<std::uint8_t>(r);
    reply(code, std::span(&byte, 1), out);
  };
  const std::uint8_t mode = data[0];
  if (mode == static_cast<std::uint8_t>(OperatingMode::Installation)) {
    const bool password_ok =
        data.size() == 9 && std::memcmp(data.data() + 1, protocol::kInstallationPassword, 8) == 0;
    if (password_ok) installation_mode_ = true;
    result(password_ok ? ModeSwitchResult::Success : ModeSwitchResult::WrongPassword);
    return;
  }
  if (data.size() != 1) {
    nak(out);
    return;
  }
  if (const auto baud = protocol::baud_for_mode(mode)) {
    if (*baud == 500000 && !identity_.supports_500k) {
      result(ModeSwitchResult::Failed);
      return;
    }
    result(ModeSwitchResult::Success);
    out.push_back(DeviceOutput{DeviceOutput::Action::SwitchBaud, {}, *baud});
    return;
  }
  switch (static_cast<OperatingMode>(mode)) {
    case OperatingMode::ContinuousAll:
      streaming_ = true;
      installation_mode_ = false;
      result(ModeSwitchResult::Success);
      return;
    case OperatingMode::OnRequest:
      streaming_ = false;
      installation_mode_ = false;
      result(ModeSwitchResult::Success);
      return;
    default:
      // Mean values and the other listed modes are not emulated: the device's "failed" reply.
      result(ModeSwitchResult::Failed);
      return;
  }
}

std::vector<std::uint8_t> Lms200Device::status_block() const {
  std::vector<std::uint8_t> block(protocol::kStatusBytes, 0);
  std::copy_n(identity_.firmware_version.begin(),
              std::min<std::size_t>(7, identity_.firmware_version.size()), block.begin());
  block[7] = static_cast<std::uint8_t>(installation_mode_ ? OperatingMode::Installation
                                       : streaming_       ? OperatingMode::ContinuousAll
                                                          : OperatingMode::OnRequest);
  block[8] = 0;  // no error
  return block;
}

ScannerOutput Lms200Device::scanner_output(const ScannerOutput& base) const {
  ScannerOutput output = base;
  const auto mode = configuration_.measuring_mode();
  const bool mm = configuration_.units() == protocol::Units::Millimetre;
  output.units = mm ? RangeUnits::Millimetre : RangeUnits::Centimetre;
  output.max_range_mm = protocol::max_distance_code(mode) * (mm ? 1.0 : 10.0);
  output.beams = variant_.values_per_scan();
  output.field_deg = variant_.angle_deg;
  return output;
}

std::vector<std::uint8_t> Lms200Device::scan_telegram(
    const std::vector<RangeReading>& readings) const {
  const auto mode = configuration_.measuring_mode();
  protocol::ScanTelegram scan;
  scan.units = configuration_.units();
  scan.status = status_byte_;
  const double unit = scan.units == protocol::Units::Millimetre ? 1.0 : 10.0;
  for (const RangeReading& r : readings) {
    std::uint16_t code = protocol::code_for_status(mode, protocol::ValueStatus::BeyondMaximum);
    const double value = std::round(r.range_mm / unit);
    if (r.status == ReadingStatus::Valid && value >= 0.0 &&
        value <= protocol::max_distance_code(mode)) {
      code = static_cast<std::uint16_t>(value);
    }
    scan.distance_codes.push_back(code);
    scan.flags.push_back(0);
  }
  // encode_scan_data ends with the status byte already.
  return protocol::encode_telegram(protocol::Telegram{
      static_cast<std::uint8_t>(protocol::kReplyFlag | protocol::kDefaultDeviceAddress),
      protocol::kScanReply, protocol::encode_scan_data(scan, mode)});
}

}  // namespace tofcomp::sim::lms200
