// Known answers: whole request telegrams as SICK's listing prints them (and as every public
// LMS 2xx driver sends them), checked byte for byte, CRC included.
#include <gtest/gtest.h>

#include "hal/lms2xx/crc16.hpp"
#include "hal/lms2xx/messages.hpp"

namespace tofcomp::hal::lms2xx {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(SickCrc16, RateChangeTelegramsOfTheListing) {
  EXPECT_EQ(encode_telegram(switch_mode_request(OperatingMode::Baud38400)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x40, 0x50, 0x08}));
  EXPECT_EQ(encode_telegram(switch_mode_request(OperatingMode::Baud19200)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x41, 0x51, 0x08}));
  EXPECT_EQ(encode_telegram(switch_mode_request(OperatingMode::Baud9600)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x42, 0x52, 0x08}));
  EXPECT_EQ(encode_telegram(switch_mode_request(OperatingMode::Baud500000)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x48, 0x58, 0x08}));
}

TEST(SickCrc16, StreamingAndInstallationTelegramsOfTheListing) {
  EXPECT_EQ(encode_telegram(switch_mode_request(OperatingMode::ContinuousAll)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}));
  EXPECT_EQ(encode_telegram(switch_mode_request(OperatingMode::OnRequest)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08}));
  EXPECT_EQ(encode_telegram(installation_mode_request()),
            (Bytes{0x02, 0x00, 0x0A, 0x00, 0x20, 0x00, 'S', 'I', 'C', 'K', '_', 'L', 'M', 'S',
                   0xBE, 0xC5}));
  EXPECT_EQ(encode_telegram(status_request()), (Bytes{0x02, 0x00, 0x01, 0x00, 0x31, 0x15, 0x12}));
}

TEST(SickCrc16, EmptyInputIsZeroAndEveryByteMatters) {
  EXPECT_EQ(sick_crc16({}), 0);
  Bytes telegram{0x02, 0x00, 0x02, 0x00, 0x20, 0x40};
  const std::uint16_t good = sick_crc16(telegram);
  for (std::size_t i = 0; i < telegram.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes flipped = telegram;
      flipped[i] ^= static_cast<std::uint8_t>(1u << bit);
      EXPECT_NE(sick_crc16(flipped), good) << "byte " << i << " bit " << bit;
    }
  }
}

}  // namespace
}  // namespace tofcomp::hal::lms2xx
