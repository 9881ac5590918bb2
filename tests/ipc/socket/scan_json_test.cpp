// The scan encoder against a scan written out by hand: every field, null for what does not
// exist, flag names, posteriors of the calibration's modes only, sub-ranges of beams.
#include "ipc/socket/scan_json.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

namespace tofcomp::ipc::socket {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

CompensatedScan known_scan() {
  CompensatedScan s;
  s.sequence = 12;
  s.device_sequence = 10;
  s.timestamp_ns = 1700000000123456789;
  s.junction_c = 41.5;
  s.junction_std_c = 0.25;
  s.case_c = kNaN;
  s.start_angle_deg = 0.0;
  s.resolution_deg = 0.5;
  s.calibration_id = 3;
  BeamValue echo;
  echo.raw_mm = 2000;
  echo.compensated_mm = 1987.125;
  echo.window_mm = 1987.5;
  echo.window_std_mm = 0.75;
  echo.mode_posterior = {0.75f, 0.25f, 0.0f, 0.0f};
  echo.mode_count = 2;
  echo.most_probable_mode = 0;
  echo.flags = kBeamChangeDetected;
  BeamValue none;
  none.raw_mm = 8183;
  none.compensated_mm = kNaN;
  none.window_mm = kNaN;
  none.window_std_mm = std::numeric_limits<double>::infinity();
  none.flags = kBeamNoEcho | kBeamUncalibrated | (1u << 9);
  BeamValue third = echo;
  third.raw_mm = 2001;
  third.flags = 0;
  third.mode_posterior = {0.1f, 0.2f, 0.7f, 0.9f};  // the fourth is not a mode of the calibration
  third.mode_count = 3;
  third.most_probable_mode = 2;
  s.beams = {echo, none, third};
  return s;
}

TEST(ScanJson, KnownScanByteForByte) {
  const std::string expected =
      R"({"sequence":12,"device_sequence":10,"timestamp_ns":1700000000123456789,"rays":null,)"
      R"("junction_c":41.5,"junction_std_c":0.25,"case_c":null,"start_angle_deg":0,)"
      R"("resolution_deg":0.5,"calibration_id":3,"beam_count":3,"first_beam":0,"beams":[)"
      R"({"index":0,"raw_mm":2000,"compensated_mm":1987.125,"window_mm":1987.5,)"
      R"("window_std_mm":0.75,"flags":16,"flag_names":["change_detected"],"mode_count":2,)"
      R"("most_probable_mode":0,"mode_posterior":[0.75,0.25]},)"
      R"({"index":1,"raw_mm":8183,"compensated_mm":null,"window_mm":null,)"
      R"("window_std_mm":null,"flags":515,"flag_names":["no_echo","uncalibrated","bit9"],)"
      R"("mode_count":0,"most_probable_mode":0,"mode_posterior":[]},)"
      R"({"index":2,"raw_mm":2001,"compensated_mm":1987.125,"window_mm":1987.5,)"
      R"("window_std_mm":0.75,"flags":0,"flag_names":[],"mode_count":3,)"
      R"("most_probable_mode":2,"mode_posterior":[0.1,0.2,0.7]}]})";
  EXPECT_EQ(encode_scan(known_scan(), {0, 3}), expected);
}

TEST(ScanJson, EncodedScanIsJsonThatReadsBackToTheSameNumbers) {
  CompensatedScan s = known_scan();
  s.beams[0].compensated_mm = 1987.1234567890123;
  s.junction_c = -3.0e-7;
  const auto doc = nlohmann::json::parse(encode_scan(s, {0, 3}));
  EXPECT_EQ(doc["beams"][0]["compensated_mm"].get<double>(), 1987.1234567890123);
  EXPECT_EQ(doc["junction_c"].get<double>(), -3.0e-7);
  EXPECT_TRUE(doc["case_c"].is_null());
  EXPECT_EQ(doc["beams"][2]["mode_posterior"][0].get<double>(), 0.1);
}

TEST(ScanJson, SubRangeKeepsBeamIndicesAndTheScansBeamCount) {
  const auto doc = nlohmann::json::parse(encode_scan(known_scan(), {1, 2}));
  EXPECT_EQ(doc["beam_count"], 3);
  EXPECT_EQ(doc["first_beam"], 1);
  ASSERT_EQ(doc["beams"].size(), 2u);
  EXPECT_EQ(doc["beams"][0]["index"], 1);
  EXPECT_EQ(doc["beams"][1]["index"], 2);
  EXPECT_EQ(doc["beams"][1]["raw_mm"], 2001);
}

TEST(ScanJson, EmptySpanGivesNoBeams) {
  const auto doc = nlohmann::json::parse(encode_scan(known_scan(), {5, 0}));
  EXPECT_EQ(doc["first_beam"], 5);
  EXPECT_TRUE(doc["beams"].empty());
}

TEST(ScanJson, SpanOutsideTheScanIsAnError) {
  EXPECT_THROW(encode_scan(known_scan(), {2, 2}), core::InvalidInput);
  EXPECT_THROW(encode_scan(known_scan(), {3, 1}), core::InvalidInput);
}

TEST(ScanJson, DecodedScanIsTheEncodedOneWithNullAsNaN) {
  const CompensatedScan s = known_scan();
  const ReceivedScan r = decode_scan(nlohmann::json::parse(encode_scan(s, {1, 2})));
  EXPECT_EQ(r.span, (BeamSpan{1, 2}));
  EXPECT_EQ(r.scan.sequence, 12u);
  EXPECT_EQ(r.scan.device_sequence, 10u);
  EXPECT_EQ(r.scan.timestamp_ns, 1700000000123456789);
  EXPECT_EQ(r.scan.junction_c, 41.5);
  EXPECT_EQ(r.scan.junction_std_c, 0.25);
  EXPECT_TRUE(std::isnan(r.scan.case_c));
  EXPECT_EQ(r.scan.resolution_deg, 0.5);
  EXPECT_EQ(r.scan.calibration_id, 3u);
  ASSERT_EQ(r.scan.beams.size(), 3u);
  const BeamValue& none = r.scan.beams[1];
  EXPECT_EQ(none.raw_mm, 8183);
  EXPECT_TRUE(std::isnan(none.compensated_mm));
  EXPECT_TRUE(std::isnan(none.window_std_mm));  // infinite on the daemon's side: null
  EXPECT_EQ(none.flags, kBeamNoEcho | kBeamUncalibrated | (1u << 9));
  const BeamValue& third = r.scan.beams[2];
  EXPECT_EQ(third.compensated_mm, 1987.125);
  EXPECT_EQ(third.mode_count, 3);
  EXPECT_EQ(third.most_probable_mode, 2);
  EXPECT_EQ(third.mode_posterior, (std::array<float, kMaxModes>{0.1f, 0.2f, 0.7f, 0.0f}));
}

TEST(ScanJson, RaysTimingRoundTripsAndUnknownIsNull) {
  CompensatedScan s = known_scan();
  s.rays = {1700000000088852085, 37037.037037037036, 13333333.333333334, 2};
  const auto doc = nlohmann::json::parse(encode_scan(s, {0, 1}));
  EXPECT_EQ(doc["rays"]["first_ray_ns"].get<std::int64_t>(), 1700000000088852085);
  EXPECT_EQ(doc["rays"]["interlaced_turns"], 2);
  const ReceivedScan r = decode_scan(doc);
  EXPECT_EQ(r.scan.rays.first_ray_ns, s.rays.first_ray_ns);
  EXPECT_EQ(r.scan.rays.ray_interval_ns, s.rays.ray_interval_ns);
  EXPECT_EQ(r.scan.rays.turn_period_ns, s.rays.turn_period_ns);
  EXPECT_EQ(r.scan.rays.interlaced_turns, 2u);
  // Unknown (a recording's scans): null, and read back as unknown; so is an older daemon's scan
  // without the member.
  auto unknown = nlohmann::json::parse(encode_scan(known_scan(), {0, 1}));
  EXPECT_TRUE(unknown["rays"].is_null());
  EXPECT_FALSE(decode_scan(unknown).scan.rays.known());
  unknown.erase("rays");
  EXPECT_FALSE(decode_scan(unknown).scan.rays.known());
  // More interlaced turns than any LMS 2xx takes is a malformed scan.
  auto malformed = doc;
  malformed["rays"]["interlaced_turns"] = 1000;
  EXPECT_THROW(decode_scan(malformed), core::InvalidInput);
}

TEST(ScanJson, DecodingWhatIsNoScanObjectIsAnError) {
  auto doc = nlohmann::json::parse(encode_scan(known_scan(), {0, 3}));
  doc.erase("calibration_id");
  EXPECT_THROW(decode_scan(doc), core::InvalidInput);
  doc = nlohmann::json::parse(encode_scan(known_scan(), {0, 3}));
  doc["beam_count"] = 2;  // three beams sent of a scan of two
  EXPECT_THROW(decode_scan(doc), core::InvalidInput);
}

TEST(FlagNames, EveryNamedBitAndUnnamedOnes) {
  EXPECT_TRUE(beam_flag_names(0).empty());
  EXPECT_EQ(beam_flag_names(kBeamNoEcho | kBeamUncalibrated | kBeamTemperatureStale |
                            kBeamWindowRestarting | kBeamChangeDetected | kBeamOutlier),
            (std::vector<std::string>{"no_echo", "uncalibrated", "temperature_stale",
                                      "window_restarting", "change_detected", "outlier"}));
  EXPECT_EQ(beam_flag_names(0x8040),
            (std::vector<std::string>{"temperature_extrapolated", "bit15"}));
  EXPECT_EQ(beam_flag_names(0x8080), (std::vector<std::string>{"bit7", "bit15"}));
}

TEST(BeamSpans, ExactlyAcceptsRangesWithinTheScan) {
  EXPECT_EQ(beams_exactly(std::nullopt, 361), (BeamSpan{0, 361}));
  EXPECT_EQ(beams_exactly(BeamRange{0, 360}, 361), (BeamSpan{0, 361}));
  EXPECT_EQ(beams_exactly(BeamRange{180, 180}, 361), (BeamSpan{180, 1}));
  EXPECT_EQ(beams_exactly(std::nullopt, 0), (BeamSpan{0, 0}));
}

TEST(BeamSpans, ExactlyRejectsRangesBeyondTheScanNamingBeams) {
  try {
    beams_exactly(BeamRange{100, 400}, 361);
    FAIL();
  } catch (const ProtocolError& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadRange);
    EXPECT_STREQ(e.what(),
                 "beams: [100, 400] reaches beyond the scan, which has 361 beams (0..360)");
  }
  EXPECT_THROW(beams_exactly(BeamRange{0, 0}, 0), ProtocolError);
}

TEST(BeamSpans, ClippedKeepsWhatTheScanHas) {
  EXPECT_EQ(beams_clipped(BeamRange{300, 400}, 361), (BeamSpan{300, 61}));
  EXPECT_EQ(beams_clipped(BeamRange{361, 400}, 361), (BeamSpan{361, 0}));
  EXPECT_EQ(beams_clipped(BeamRange{10, 20}, 361), (BeamSpan{10, 11}));
  EXPECT_EQ(beams_clipped(std::nullopt, 181), (BeamSpan{0, 181}));
}

}  // namespace
}  // namespace tofcomp::ipc::socket
