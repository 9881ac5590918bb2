#include "hal/lms2xx/messages.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace tofcomp::hal::lms2xx {
namespace {

TEST(Messages, VariantRequestCarriesAngleAndResolution) {
  const Telegram t = variant_request({100, 25});
  EXPECT_EQ(t.command, 0x3B);
  EXPECT_EQ(t.data, (std::vector<std::uint8_t>{100, 0, 25, 0}));
  EXPECT_EQ(Variant({100, 25}).values_per_scan(), 401);
  EXPECT_EQ(Variant({180, 50}).values_per_scan(), 361);
  EXPECT_EQ(Variant({180, 100}).values_per_scan(), 181);
  EXPECT_FALSE(Variant({180, 25}).is_valid());
}

TEST(Messages, RepliesRoundTripThroughTheirParsers) {
  const std::vector<std::uint8_t> accepted{0x01, 180, 0, 50, 0};
  const VariantReply v = parse_variant_reply(make_reply(0xBB, accepted, 0));
  EXPECT_TRUE(v.accepted);
  EXPECT_EQ(v.active, (Variant{180, 50}));

  const std::vector<std::uint8_t> wrong_password{0x01};
  EXPECT_EQ(parse_mode_switch_reply(make_reply(0xA0, wrong_password, 0)),
            ModeSwitchResult::WrongPassword);

  ConfigurationBlock block;
  block.set_units(Units::Centimetre);
  const auto bytes = block.bytes();
  EXPECT_EQ(parse_configuration_reply(make_reply(0xF4, bytes, 0)).units(), Units::Centimetre);

  const std::string type = "LMS200;30106";
  const std::vector<std::uint8_t> type_bytes(type.begin(), type.end());
  EXPECT_EQ(parse_type_reply(make_reply(0xBA, type_bytes, 0)), type);
}

TEST(Messages, AReplyOfTheWrongCodeOrLengthIsNamed) {
  const std::vector<std::uint8_t> one{0x00};
  EXPECT_THROW(parse_variant_reply(make_reply(0xA0, one, 0)), core::InvalidInput);
  EXPECT_THROW(parse_variant_reply(make_reply(0xBB, one, 0)), core::InvalidInput);
  EXPECT_THROW(parse_status_reply(make_reply(0xB1, one, 0)), core::InvalidInput);
  const std::vector<std::uint8_t> bad_units(ConfigurationBlock::kBytes, 7);
  EXPECT_THROW(parse_configuration_reply(make_reply(0xF4, bad_units, 0)), core::InvalidInput);
}

TEST(Messages, BaudRatesMapToTheirModeBytes) {
  for (const unsigned baud : kSupportedBauds) {
    const auto mode = mode_for_baud(baud);
    ASSERT_TRUE(mode.has_value());
    EXPECT_EQ(baud_for_mode(static_cast<std::uint8_t>(*mode)), baud);
  }
  EXPECT_FALSE(mode_for_baud(115200).has_value());
  EXPECT_FALSE(baud_for_mode(0x24).has_value());
}

}  // namespace
}  // namespace tofcomp::hal::lms2xx
