// Compact frames: the bytes at the offsets docs/protocol.md gives, a round trip of every value a
// frame carries, and a refusal naming the field for each way a hostile frame can be wrong.
#include "ipc/socket/compact_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tofcomp::ipc::socket {
namespace {

CompensatedScan three_beam_scan() {
  CompensatedScan scan;
  scan.sequence = 0x0102030405060708ull;
  scan.device_sequence = 9;
  scan.timestamp_ns = 1700000000123456789;
  scan.junction_c = 41.25;
  scan.junction_std_c = 0.125;
  scan.case_c = std::numeric_limits<double>::quiet_NaN();
  scan.start_angle_deg = 0.0;
  scan.resolution_deg = 0.5;
  scan.calibration_id = 3;
  scan.rays = {1700000000088852085, 37037.037037037036, 13333333.333333334, 2};
  scan.beams.resize(3);
  scan.beams[0].compensated_mm = 1988.25;
  scan.beams[1].compensated_mm = 2000.5;
  scan.beams[1].flags = kBeamWindowRestarting | kBeamChangeDetected;
  scan.beams[2].compensated_mm = std::numeric_limits<double>::quiet_NaN();
  scan.beams[2].flags = kBeamNoEcho;
  return scan;
}

unsigned byte(const std::string& frame, std::size_t offset) {
  return static_cast<unsigned char>(frame[offset]);
}

TEST(CompactFrame, BytesLieAtTheDocumentedOffsetsLittleEndian) {
  const std::string frame = encode_compact_frame(three_beam_scan(), {1, 2});
  ASSERT_EQ(frame.size(), 128u + 2 * 6);
  EXPECT_EQ(frame.substr(0, 4), std::string("\x89TCS"));
  EXPECT_EQ(byte(frame, 4), 1u);    // version 1
  EXPECT_EQ(byte(frame, 6), 128u);  // header size
  EXPECT_EQ(byte(frame, 8), 140u);  // frame size 128 + 12
  EXPECT_EQ(byte(frame, 12), 3u);   // calibration id
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(byte(frame, 16 + i), 8 - i) << i;  // sequence
  EXPECT_EQ(byte(frame, 24), 9u);                                                  // device seq.
  double junction = 0;
  std::memcpy(&junction, frame.data() + 40, sizeof junction);  // this host is little-endian
  EXPECT_EQ(junction, 41.25);
  EXPECT_EQ(byte(frame, 80), 3u);  // beam_count
  EXPECT_EQ(byte(frame, 84), 1u);  // first_beam
  EXPECT_EQ(byte(frame, 88), 2u);  // count
  std::int64_t first_ray = 0;
  std::memcpy(&first_ray, frame.data() + 96, sizeof first_ray);
  EXPECT_EQ(first_ray, three_beam_scan().rays.first_ray_ns);
  double turn_period = 0;
  std::memcpy(&turn_period, frame.data() + 112, sizeof turn_period);
  EXPECT_EQ(turn_period, three_beam_scan().rays.turn_period_ns);
  EXPECT_EQ(byte(frame, 120), 2u);  // interlaced_turns
  float range = 0;
  std::memcpy(&range, frame.data() + 128, sizeof range);
  EXPECT_EQ(range, 2000.5f);
  std::memcpy(&range, frame.data() + 132, sizeof range);
  EXPECT_TRUE(std::isnan(range));
  EXPECT_EQ(byte(frame, 136), 24u);  // flags of beam 1: 8 | 16
  EXPECT_EQ(byte(frame, 138), 1u);   // flags of beam 2: no_echo
}

TEST(CompactFrame, RoundTripKeepsTheHeaderAndTheSentBeams) {
  const CompensatedScan scan = three_beam_scan();
  const ReceivedScan back = decode_compact_frame(encode_compact_frame(scan, {0, 3}));
  EXPECT_EQ(back.span, (BeamSpan{0, 3}));
  EXPECT_EQ(back.scan.sequence, scan.sequence);
  EXPECT_EQ(back.scan.device_sequence, scan.device_sequence);
  EXPECT_EQ(back.scan.timestamp_ns, scan.timestamp_ns);
  EXPECT_EQ(back.scan.junction_c, scan.junction_c);
  EXPECT_EQ(back.scan.junction_std_c, scan.junction_std_c);
  EXPECT_TRUE(std::isnan(back.scan.case_c));
  EXPECT_EQ(back.scan.resolution_deg, 0.5);
  EXPECT_EQ(back.scan.calibration_id, 3u);
  EXPECT_EQ(back.scan.rays.first_ray_ns, scan.rays.first_ray_ns);
  EXPECT_EQ(back.scan.rays.ray_interval_ns, scan.rays.ray_interval_ns);
  EXPECT_EQ(back.scan.rays.turn_period_ns, scan.rays.turn_period_ns);
  EXPECT_EQ(back.scan.rays.interlaced_turns, 2u);
  ASSERT_EQ(back.scan.beams.size(), 3u);
  EXPECT_EQ(back.scan.beams[0].compensated_mm, 1988.25);
  EXPECT_EQ(back.scan.beams[1].flags, kBeamWindowRestarting | kBeamChangeDetected);
  EXPECT_TRUE(std::isnan(back.scan.beams[2].compensated_mm));
  EXPECT_TRUE(std::isnan(back.scan.beams[0].raw_mm));  // not carried
}

TEST(CompactFrame, AnEmptySpanIsAHeaderAlone) {
  const std::string frame = encode_compact_frame(three_beam_scan(), {3, 0});
  EXPECT_EQ(frame.size(), kCompactHeaderBytes);
  EXPECT_EQ(decode_compact_frame(frame).span.count, 0u);
}

void expect_refused(const std::string& frame, const std::string& naming) {
  try {
    decode_compact_frame(frame);
    ADD_FAILURE() << "accepted; expected a refusal naming " << naming;
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(naming), std::string::npos) << e.what();
  }
}

void set_u32(std::string& frame, std::size_t offset, std::uint32_t value) {
  for (std::size_t i = 0; i < 4; ++i) frame[offset + i] = static_cast<char>(value >> (8 * i));
}

TEST(CompactFrame, HostileFramesAreRefusedNamingTheField) {
  const std::string good = encode_compact_frame(three_beam_scan(), {0, 3});
  expect_refused(good.substr(0, 127), "fewer than the 128 of its header");
  expect_refused(good.substr(0, good.size() - 1), "bytes where its header says");
  expect_refused(good + "x", "bytes where its header says");
  std::string bad = good;
  bad[1] = 'X';
  expect_refused(bad, "magic");
  bad = good;
  bad[4] = 2;
  expect_refused(bad, "version (offset 4) is 2");
  bad = good;
  bad[6] = 64;
  expect_refused(bad, "header size (offset 6) is 64");
  bad = good;
  set_u32(bad, 8, 0xFFFFFFF0u);
  expect_refused(bad, "frame size (offset 8)");
  bad = good;
  set_u32(bad, 80, 70000);
  expect_refused(bad, "beam_count (offset 80) is 70000");
  bad = good;
  set_u32(bad, 84, 0xFFFFFFFFu);  // first + count overflows 32 bits
  expect_refused(bad, "reach beyond the scan's 3");
  bad = good;
  set_u32(bad, 88, 4);
  expect_refused(bad, "reach beyond the scan's 3");
  bad = good;
  set_u32(bad, 120, 1000);
  expect_refused(bad, "interlaced_turns (offset 120) is 1000");
}

}  // namespace
}  // namespace tofcomp::ipc::socket
