// Round trips through the ring: a scan with known values (NaN and every flag included) comes
// back bit for bit; the bytes sit at the offsets docs/shm-ring.md gives; bad names, counts and
// oversized scans are errors that name the object.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::difference;
using testing::known_scan;
using testing::RawShm;
using testing::ScopedRingName;

// A scan whose beams cover every documented case: no echo (all NaN), uncalibrated (NaN
// compensation and window), a window still filling, and every flag at once.
CompensatedScan scan_with_missing_values() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CompensatedScan scan;
  scan.sequence = 41;
  scan.device_sequence = 9001;
  scan.timestamp_ns = 1'715'000'000'123'456'789;
  scan.junction_c = nan;
  scan.junction_std_c = nan;
  scan.case_c = 26.5;
  scan.start_angle_deg = 0.0;
  scan.resolution_deg = 0.5;
  scan.calibration_id = 0;
  BeamValue no_echo;
  no_echo.raw_mm = nan;
  no_echo.compensated_mm = nan;
  no_echo.window_mm = nan;
  no_echo.window_std_mm = nan;
  no_echo.flags = kBeamNoEcho;
  BeamValue uncalibrated;
  uncalibrated.raw_mm = 2999.0;
  uncalibrated.compensated_mm = nan;
  uncalibrated.window_mm = nan;
  uncalibrated.window_std_mm = nan;
  uncalibrated.flags = kBeamUncalibrated | kBeamTemperatureStale;
  BeamValue filling;
  filling.raw_mm = 3001.0;
  filling.compensated_mm = 2987.25;
  filling.window_mm = nan;
  filling.window_std_mm = nan;
  filling.mode_posterior = {0.75f, 0.25f, 0.0f, 0.0f};
  filling.flags = kBeamWindowRestarting;
  filling.mode_count = 2;
  filling.most_probable_mode = 0;
  BeamValue every_flag;
  every_flag.raw_mm = 3010.0;
  every_flag.compensated_mm = 2990.5;
  every_flag.window_mm = 2990.0;
  every_flag.window_std_mm = 1.5;
  every_flag.mode_posterior = {0.125f, 0.5f, 0.25f, 0.125f};
  every_flag.flags = kBeamNoEcho | kBeamUncalibrated | kBeamTemperatureStale |
                     kBeamWindowRestarting | kBeamChangeDetected;
  every_flag.mode_count = 4;
  every_flag.most_probable_mode = 1;
  scan.beams = {no_echo, uncalibrated, filling, every_flag};
  return scan;
}

TEST(RingRoundTrip, ScanWithNanAndEveryFlagComesBackUnchanged) {
  const ScopedRingName name("roundtrip");
  RingWriter writer(name, 4, 16);
  RingReader reader(name);
  EXPECT_FALSE(reader.latest().has_value());
  const CompensatedScan sent = scan_with_missing_values();
  writer.publish(sent);

  const auto latest = reader.latest();
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(difference(*latest, sent), "");
  EXPECT_TRUE(std::isnan(latest->junction_c));
  EXPECT_TRUE(std::isnan(latest->beams[0].raw_mm));
  EXPECT_EQ(latest->beams[0].flags, kBeamNoEcho);
  EXPECT_EQ(latest->beams[3].flags, 0x1F);
  EXPECT_EQ(latest->beams[2].compensated_mm, 2987.25);

  const ReadBatch batch = reader.read_new();
  ASSERT_EQ(batch.scans.size(), 1u);
  EXPECT_EQ(difference(batch.scans[0], sent), "");
  EXPECT_EQ(batch.lost, 0u);
  EXPECT_FALSE(batch.writer_restarted);
  EXPECT_TRUE(reader.read_new().scans.empty());
}

TEST(RingRoundTrip, NanPayloadBitsAreKept) {
  const ScopedRingName name("nanbits");
  RingWriter writer(name, 2, 1);
  RingReader reader(name);
  CompensatedScan scan = known_scan(0, 1);
  scan.beams[0].window_mm = std::nan("1234");
  writer.publish(scan);
  const auto got = reader.latest();
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(std::memcmp(&got->beams[0].window_mm, &scan.beams[0].window_mm, sizeof(double)), 0);
}

TEST(RingRoundTrip, EmptyAndFullScansRoundTrip) {
  const ScopedRingName name("sizes");
  RingWriter writer(name, 3, 721);
  RingReader reader(name);
  writer.publish(known_scan(0, 0));
  writer.publish(known_scan(1, 721));
  writer.publish(known_scan(2, 361));
  reader.rewind_to_oldest();
  const ReadBatch batch = reader.read_new();
  ASSERT_EQ(batch.scans.size(), 3u);
  EXPECT_EQ(difference(batch.scans[0], known_scan(0, 0)), "");
  EXPECT_EQ(difference(batch.scans[1], known_scan(1, 721)), "");
  EXPECT_EQ(difference(batch.scans[2], known_scan(2, 361)), "");
}

TEST(RingRoundTrip, TooManyBeamsIsAnErrorAndPublishesNothing) {
  const ScopedRingName name("toomany");
  RingWriter writer(name, 4, 361);
  RingReader reader(name);
  writer.publish(known_scan(0, 361));
  try {
    writer.publish(known_scan(1, 362));
    FAIL() << "a scan of 362 beams was accepted by a ring of 361";
  } catch (const core::InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(name.str()), std::string::npos) << message;
    EXPECT_NE(message.find("362 beams"), std::string::npos) << message;
    EXPECT_NE(message.find("361"), std::string::npos) << message;
  }
  EXPECT_EQ(writer.published(), 1u);
  EXPECT_EQ(reader.info().published, 1u);
  EXPECT_EQ(reader.latest()->sequence, 0u);
}

TEST(RingRoundTrip, BytesSitAtTheDocumentedOffsets) {
  const ScopedRingName name("offsets");
  RingWriter writer(name, 4, 8);
  for (std::uint64_t s = 0; s < 5; ++s) writer.publish(known_scan(s, 3));
  const RawShm raw(name);
  // 112 + 8 * 56 = 560 bytes, rounded up to 576; 128 + 4 * 576 = 2432.
  EXPECT_EQ(raw.size(), 2432u);
  EXPECT_EQ(std::memcmp(raw.bytes(), "TOFCRING", 8), 0);
  EXPECT_EQ(raw.get<std::uint32_t>(8), 2u);
  EXPECT_EQ(raw.bytes()[12], 0x04);
  EXPECT_EQ(raw.bytes()[15], 0x01);
  EXPECT_EQ(raw.get<std::uint32_t>(16), 128u);
  EXPECT_EQ(raw.get<std::uint32_t>(20), 576u);
  EXPECT_EQ(raw.get<std::uint32_t>(24), 4u);
  EXPECT_EQ(raw.get<std::uint32_t>(28), 8u);
  EXPECT_EQ(raw.get<std::uint32_t>(32), 4u);
  EXPECT_EQ(raw.get<std::uint32_t>(36), 112u);
  EXPECT_EQ(raw.get<std::uint32_t>(40), 56u);
  EXPECT_EQ(raw.get<std::int32_t>(44), static_cast<std::int32_t>(::getpid()));
  EXPECT_EQ(raw.get<std::uint64_t>(48), writer.generation());
  EXPECT_EQ(raw.get<std::uint32_t>(56), 1u);  // writer alive
  EXPECT_EQ(raw.get<std::uint64_t>(64), 5u);  // published

  // Publish 4 went to slot 0 (seq 2*4+2), publish 1 is still in slot 1 (seq 4).
  const std::size_t slot0 = 128;
  const std::size_t slot1 = 128 + 576;
  EXPECT_EQ(raw.get<std::uint64_t>(slot0), 10u);
  EXPECT_EQ(raw.get<std::uint64_t>(slot1), 4u);
  EXPECT_EQ(raw.get<std::uint64_t>(slot0 + 8), 4u);           // sequence
  EXPECT_EQ(raw.get<std::uint64_t>(slot0 + 16), 3u * 4 + 7);  // device_sequence
  EXPECT_EQ(raw.get<double>(slot0 + 32), 25.0 + 0.25 * 4);    // junction_c
  EXPECT_EQ(raw.get<std::uint32_t>(slot0 + 72), 4u);          // calibration_id
  EXPECT_EQ(raw.get<std::uint32_t>(slot0 + 76), 3u);          // beam_count
  const CompensatedScan published4 = known_scan(4, 3);
  EXPECT_EQ(raw.get<std::int64_t>(slot0 + 80), published4.rays.first_ray_ns);
  EXPECT_EQ(raw.get<double>(slot0 + 88), published4.rays.ray_interval_ns);
  EXPECT_EQ(raw.get<double>(slot0 + 96), published4.rays.turn_period_ns);
  EXPECT_EQ(raw.get<std::uint32_t>(slot0 + 104), 2u);  // interlaced_turns
  EXPECT_EQ(raw.get<std::uint32_t>(slot0 + 108), 0u);  // reserved
  const std::size_t beam2 = slot0 + 112 + 2 * 56;
  EXPECT_EQ(raw.get<double>(beam2), 400002.0);        // raw_mm
  EXPECT_EQ(raw.get<double>(beam2 + 8), 400001.5);    // compensated_mm
  EXPECT_EQ(raw.get<double>(beam2 + 16), 400001.75);  // window_mm
  EXPECT_EQ(raw.get<double>(beam2 + 24), 0.25);       // window_std_mm
  EXPECT_EQ(raw.get<float>(beam2 + 32), 4.0f);        // mode_posterior[0]
  EXPECT_EQ(raw.get<float>(beam2 + 44), 0.125f);      // mode_posterior[3]
  EXPECT_EQ(raw.get<std::uint16_t>(beam2 + 48), 6u);  // flags (4 + 2)
  EXPECT_EQ(raw.bytes()[beam2 + 50], 1u);             // mode_count
  EXPECT_EQ(raw.bytes()[beam2 + 51], 0u);             // most_probable_mode
}

TEST(RingRoundTrip, ObjectHasTheConfiguredModeWhateverTheUmask) {
  const ScopedRingName name("mode");
  const mode_t old_umask = ::umask(0077);
  {
    RingWriter writer(name, 2, 1);
    struct stat st {};
    ASSERT_EQ(::stat(("/dev/shm" + name.str()).c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0640u);
  }
  {
    RingWriter writer(name, 2, 1, RingWriterOptions{0604, false});
    struct stat st {};
    ASSERT_EQ(::stat(("/dev/shm" + name.str()).c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0604u);
  }
  ::umask(old_umask);
}

TEST(RingRoundTrip, DestroyedWriterRemovesTheNameUnlessKept) {
  const ScopedRingName name("unlink");
  { RingWriter writer(name, 2, 4); }
  EXPECT_THROW(RingReader{name.str()}, core::Error);
  {
    RingWriter writer(name, 2, 4, RingWriterOptions{0640, true});
    writer.publish(known_scan(7, 4));
  }
  RingReader reader(name);
  EXPECT_TRUE(reader.info().writer_closed);
  EXPECT_FALSE(reader.writer_running());
  ASSERT_TRUE(reader.latest().has_value());
  EXPECT_EQ(difference(*reader.latest(), known_scan(7, 4)), "");
}

TEST(RingRoundTrip, BadNamesAndCountsAreErrorsNamingThem) {
  const auto message_of = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const core::InvalidInput& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(message_of([] { RingWriter w("tofcompd"); }).find("'tofcompd'"), std::string::npos);
  EXPECT_NE(message_of([] { RingWriter w("/a/b"); }).find("'/a/b'"), std::string::npos);
  EXPECT_NE(message_of([] { RingWriter w("/"); }).find("'/'"), std::string::npos);
  EXPECT_NE(message_of([] { RingWriter w("/tofcomp-test-counts", 1, 10); }).find("slot count 1"),
            std::string::npos);
  EXPECT_NE(message_of([] { RingWriter w("/tofcomp-test-counts", 4, 0); }).find("max beams 0"),
            std::string::npos);
  EXPECT_NE(message_of([] { RingWriter w("/tofcomp-test-counts", 1u << 20, 65535); }).find("bytes"),
            std::string::npos);
  EXPECT_NE(message_of([] { RingReader r("no-slash"); }).find("'no-slash'"), std::string::npos);
}

TEST(RingRoundTrip, MissingRingIsAnErrorNamingIt) {
  const ScopedRingName name("missing");
  try {
    RingReader reader(name);
    FAIL() << "opened a ring that does not exist";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + name.str() + "' does not exist"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::ipc::ring
