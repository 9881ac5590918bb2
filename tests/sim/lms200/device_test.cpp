// The emulated LMS 200 answers as the telegram listing says the device answers: ACK then the
// reply; NAK for what it rejects; installation mode only with the password; configuration
// only in installation mode; state lost on a reset.
#include "sim/lms200/device.hpp"

#include <gtest/gtest.h>

#include "hal/lms2xx/crc16.hpp"
#include "hal/lms2xx/messages.hpp"

namespace tofcomp::sim::lms200 {
namespace {

namespace p = tofcomp::hal::lms2xx;
using Action = DeviceOutput::Action;

// Sends one request; returns the device's outputs.
std::vector<DeviceOutput> ask(Lms200Device& device, const p::Telegram& request) {
  std::vector<DeviceOutput> out;
  device.receive(p::encode_telegram(request), out);
  return out;
}

// The reply telegram inside an ACK + telegram output.
p::Telegram reply_of(const std::vector<DeviceOutput>& out) {
  EXPECT_FALSE(out.empty());
  const auto& bytes = out.front().bytes;
  EXPECT_GE(bytes.size(), 8u);
  EXPECT_EQ(bytes.front(), p::kAck);
  p::TelegramDecoder decoder(p::Sender::Device);
  p::Telegram reply;
  decoder.feed(std::span(bytes).subspan(1), [&](const p::DecoderEvent& e) {
    if (e.kind == p::DecoderEvent::Kind::Telegram) reply = *e.telegram;
  });
  return reply;
}

TEST(Lms200Device, StatusIsAcknowledgedThenAnswered) {
  Lms200Device device;
  const p::Telegram reply = reply_of(ask(device, p::status_request()));
  EXPECT_EQ(reply.address, 0x80);
  EXPECT_EQ(reply.command, 0xB1);
  const p::StatusReply status = p::parse_status_reply(reply);
  EXPECT_EQ(status.firmware_version, "V02.10 ");
  EXPECT_EQ(status.operating_mode, 0x25);  // values on request after power-on
}

TEST(Lms200Device, UnknownCommandsWrongLengthsAndBadCrcsAreNaked) {
  Lms200Device device;
  for (const p::Telegram& bad :
       {p::Telegram{0, 0x55, {}}, p::Telegram{0, 0x31, {0x00}}, p::Telegram{0, 0x3B, {180, 0}}}) {
    const auto out = ask(device, bad);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].bytes, std::vector<std::uint8_t>{p::kNak});
  }
  auto corrupted = p::encode_telegram(p::status_request());
  corrupted.back() ^= 1;
  std::vector<DeviceOutput> out;
  device.receive(corrupted, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bytes, std::vector<std::uint8_t>{p::kNak});
  EXPECT_EQ(device.naks_sent(), 4u);
}

TEST(Lms200Device, ConfigurationNeedsInstallationModeAndThePassword) {
  Lms200Device device;
  p::ConfigurationBlock block;
  block.set_units(p::Units::Centimetre);
  EXPECT_FALSE(
      p::parse_configure_reply(reply_of(ask(device, p::configure_request(block)))).accepted);
  EXPECT_EQ(device.configuration().units(), p::Units::Millimetre);

  p::Telegram wrong = p::installation_mode_request();
  wrong.data[1] = 'X';
  EXPECT_EQ(p::parse_mode_switch_reply(reply_of(ask(device, wrong))),
            p::ModeSwitchResult::WrongPassword);
  EXPECT_FALSE(device.installation_mode());

  EXPECT_EQ(p::parse_mode_switch_reply(reply_of(ask(device, p::installation_mode_request()))),
            p::ModeSwitchResult::Success);
  const p::ConfigureReply stored =
      p::parse_configure_reply(reply_of(ask(device, p::configure_request(block))));
  EXPECT_TRUE(stored.accepted);
  EXPECT_EQ(stored.stored.units(), p::Units::Centimetre);
}

TEST(Lms200Device, VariantsTheDeviceLacksAreRefused) {
  Lms200Device device;
  const auto refused = p::parse_variant_reply(reply_of(ask(device, p::variant_request({180, 25}))));
  EXPECT_FALSE(refused.accepted);
  EXPECT_EQ(refused.active, (p::Variant{180, 50}));  // the active one is reported
  const auto accepted =
      p::parse_variant_reply(reply_of(ask(device, p::variant_request({100, 25}))));
  EXPECT_TRUE(accepted.accepted);
  EXPECT_EQ(device.variant().values_per_scan(), 401);
}

TEST(Lms200Device, RateChangesAfterTheReplyAndFiveHundredKiloBaudNeedsRs422) {
  Lms200Device device;
  const auto out = ask(device, p::switch_mode_request(p::OperatingMode::Baud38400));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(p::parse_mode_switch_reply(reply_of(out)), p::ModeSwitchResult::Success);
  EXPECT_EQ(out[1].action, Action::SwitchBaud);  // after the reply has gone out
  EXPECT_EQ(out[1].baud, 38400u);
  EXPECT_EQ(device.baud(), 9600u);

  DeviceIdentity rs232;
  rs232.supports_500k = false;
  Lms200Device old_unit(rs232);
  EXPECT_EQ(p::parse_mode_switch_reply(
                reply_of(ask(old_unit, p::switch_mode_request(p::OperatingMode::Baud500000)))),
            p::ModeSwitchResult::Failed);
}

TEST(Lms200Device, AResetLosesTheStateAndAnnouncesItself) {
  Lms200Device device;
  ask(device, p::variant_request({100, 100}));
  ask(device, p::switch_mode_request(p::OperatingMode::ContinuousAll));
  device.set_baud(500000);
  EXPECT_TRUE(device.streaming());
  const auto out = ask(device, p::reset_request());
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].bytes, std::vector<std::uint8_t>{p::kAck});
  EXPECT_EQ(out[1].action, Action::Restart);
  device.restart();
  EXPECT_EQ(device.baud(), 9600u);
  EXPECT_FALSE(device.streaming());
  EXPECT_EQ(device.variant(), (p::Variant{180, 50}));
  const auto hello = device.power_on_telegram();
  EXPECT_EQ(hello[4], 0x91);
}

TEST(Lms200Device, ScanTelegramsCarryTheReadingsInTheConfiguredUnits) {
  Lms200Device device;
  std::vector<RangeReading> readings(361);
  readings[0].range_mm = 3004.0;
  readings[1].status = ReadingStatus::NoEcho;
  readings[1].range_mm = 9000.0;
  const auto bytes = device.scan_telegram(readings);
  p::TelegramDecoder decoder(p::Sender::Device);
  p::ScanTelegram scan;
  decoder.feed(bytes, [&](const p::DecoderEvent& e) {
    scan = p::decode_scan_data(e.telegram->data, p::MeasuringMode::Range8m);
  });
  ASSERT_EQ(scan.distance_codes.size(), 361u);
  EXPECT_EQ(scan.units, p::Units::Millimetre);
  EXPECT_EQ(scan.distance_codes[0], 3004);
  EXPECT_EQ(p::classify_distance_code(p::MeasuringMode::Range8m, scan.distance_codes[1]),
            p::ValueStatus::BeyondMaximum);
}

}  // namespace
}  // namespace tofcomp::sim::lms200
