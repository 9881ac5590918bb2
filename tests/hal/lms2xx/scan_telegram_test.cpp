#include "hal/lms2xx/scan_telegram.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace tofcomp::hal::lms2xx {
namespace {

TEST(ScanTelegram, HeaderCarriesCountAndUnitsInTheListedBits) {
  ScanTelegram scan;
  scan.units = Units::Millimetre;
  scan.distance_codes = {3000, 8182, 0};
  scan.flags = {0, 0, 5};
  scan.status = 0x10;
  const auto data = encode_scan_data(scan, MeasuringMode::Range8m);
  ASSERT_EQ(data.size(), 2u + 6u + 1u);
  EXPECT_EQ(data[0], 3);     // count, low byte
  EXPECT_EQ(data[1], 0x40);  // bits 14-15 = 01: millimetres
  EXPECT_EQ(data[2], 3000 & 0xff);
  EXPECT_EQ(data[3], 3000 >> 8);
  EXPECT_EQ(data[7], 5 << 5);  // flags above the 13 distance bits
  EXPECT_EQ(data.back(), 0x10);
  EXPECT_EQ(decode_scan_data(data, MeasuringMode::Range8m), scan);
}

TEST(ScanTelegram, CentimetreCodesScaleToMillimetres) {
  ScanTelegram scan;
  scan.units = Units::Centimetre;
  scan.distance_codes = {301};
  scan.flags = {0};
  const auto decoded = decode_scan_data(encode_scan_data(scan, MeasuringMode::Range8m),
                                        MeasuringMode::Range8m);
  EXPECT_EQ(decoded.units, Units::Centimetre);
  EXPECT_DOUBLE_EQ(decoded.distance_mm(0), 3010.0);
}

TEST(ScanTelegram, DistanceBitsFollowTheMeasuringMode) {
  ScanTelegram scan;
  scan.distance_codes = {20000};  // needs 15 bits
  scan.flags = {1};
  EXPECT_THROW(encode_scan_data(scan, MeasuringMode::Range8m), core::InvalidInput);
  const auto data = encode_scan_data(scan, MeasuringMode::Range32m);
  EXPECT_EQ(data[3], (20000 >> 8) | 0x80);
  EXPECT_EQ(decode_scan_data(data, MeasuringMode::Range32m), scan);
}

TEST(ScanTelegram, ReservedCodesAreNotDistances) {
  EXPECT_EQ(max_distance_code(MeasuringMode::Range8m), 8182);
  EXPECT_EQ(classify_distance_code(MeasuringMode::Range8m, 8182), ValueStatus::Distance);
  EXPECT_EQ(classify_distance_code(MeasuringMode::Range8m, 0x1FF7), ValueStatus::BeyondMaximum);
  EXPECT_EQ(classify_distance_code(MeasuringMode::Range8m, 0x1FFE), ValueStatus::Dazzled);
  EXPECT_EQ(classify_distance_code(MeasuringMode::Range8m, 0x1FFF), ValueStatus::NotValid);
  for (const auto s : {ValueStatus::BeyondMaximum, ValueStatus::SignalTooSmall,
                       ValueStatus::Overflow, ValueStatus::Dazzled, ValueStatus::NotValid}) {
    EXPECT_EQ(classify_distance_code(MeasuringMode::Range16m,
                                     code_for_status(MeasuringMode::Range16m, s)),
              s);
  }
}

TEST(ScanTelegram, LengthThatDisagreesWithTheCountIsNamed) {
  ScanTelegram scan;
  scan.distance_codes = {1, 2, 3};
  scan.flags = {0, 0, 0};
  auto data = encode_scan_data(scan, MeasuringMode::Range8m);
  data.pop_back();
  data.pop_back();
  try {
    decode_scan_data(data, MeasuringMode::Range8m);
    FAIL() << "a short scan was accepted";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("announces 3 values"), std::string::npos) << e.what();
  }
}

TEST(ScanTelegram, FullScanOf401ValuesRoundTrips) {
  ScanTelegram scan;
  for (int i = 0; i < kMaxValuesPerScan; ++i) {
    scan.distance_codes.push_back(static_cast<std::uint16_t>(i * 20));
    scan.flags.push_back(0);
  }
  scan.partial = true;
  scan.partial_index = 3;
  EXPECT_EQ(decode_scan_data(encode_scan_data(scan, MeasuringMode::Range8m),
                             MeasuringMode::Range8m),
            scan);
}

}  // namespace
}  // namespace tofcomp::hal::lms2xx
