// A tofcompd recording played back as the emulated LMS 200's scanner: the recorded scans in
// order with their times and no-echo beams, the case readings and power state on the playback
// clock, and, over a real pty, the host driver receiving exactly the recorded distance codes.
#include "sim/lms200/recording_playback.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "io/measured_data_csv.hpp"
#include "io/measurement_table_builder.hpp"
#include "io/recording_format.hpp"
#include "tests/hal/lms2xx/link_harness.hpp"

namespace tofcomp::sim::lms200 {
namespace {

using namespace std::chrono_literals;

constexpr std::size_t kBeams = 361;  // the 180° / 0.5° variant the host driver configures

// The recorded scans: scan k at kScanTimes[k]; beam b ranged 1000 + 7 b + k mm, except every
// 50th beam (counting from k) which had no echo and so has no row.
constexpr double kScanTimes[] = {0.0, 0.1, 0.2, 1.0, 1.1, 1.2};
constexpr std::size_t kScans = std::size(kScanTimes);
bool recorded_no_echo(std::size_t k, std::size_t b) {
  return (b + k) % 50 == 0;
}
double recorded_range_mm(std::size_t k, std::size_t b) {
  return 1000.0 + 7.0 * b + k;
}

void append_scan(io::MeasurementTableBuilder& builder, std::size_t k, std::size_t beams) {
  std::vector<double> ranges_mm;
  std::vector<std::uint8_t> no_echo;
  for (std::size_t b = 0; b < beams; ++b) {
    ranges_mm.push_back(recorded_range_mm(k, b));
    no_echo.push_back(recorded_no_echo(k, b) ? 1 : 0);
  }
  std::vector<io::MeasurementRow> rows;
  io::append_scan_rows(kScanTimes[k], ranges_mm, no_echo, rows);
  for (const auto& row : rows) builder.append(row);
}

// Three scans with the power on, the power off from 0.3 s to 1.0 s, three scans again, and
// case readings between them, the last at 1.5 s.
io::MeasurementTable recording(std::size_t beams = kBeams) {
  io::MeasurementTableBuilder builder;
  for (const auto& m : io::recording_metadata(beams, 0.0, 0.5)) {
    builder.add_metadata(m.key, m.value);
  }
  builder.append({.time_s = 0.0, .case_temp_c = 22.5, .power = true});
  append_scan(builder, 0, beams);
  append_scan(builder, 1, beams);
  builder.append({.time_s = 0.15, .case_temp_c = 22.75});
  append_scan(builder, 2, beams);
  builder.append({.time_s = 0.3, .power = false});
  builder.append({.time_s = 0.6, .case_temp_c = 23.0});
  builder.append({.time_s = 1.0, .power = true});
  append_scan(builder, 3, beams);
  append_scan(builder, 4, beams);
  builder.append({.time_s = 1.15, .case_temp_c = 23.25});
  append_scan(builder, 5, beams);
  builder.append({.time_s = 1.5, .case_temp_c = 23.5});
  return builder.finish();
}

TEST(RecordingPlayback, PlaysTheScansInOrderWithTheirNoEchoBeams) {
  RecordingPlayback playback(recording(), "run.csv");
  EXPECT_EQ(playback.beams(), kBeams);
  ASSERT_EQ(playback.scan_count(), kScans);
  EXPECT_EQ(playback.time_s(), 0.0);
  for (std::size_t k = 0; k < kScans; ++k) {
    ASSERT_EQ(playback.next_scan_time(), kScanTimes[k]) << "scan " << k;
    const std::vector<RangeReading> scan = playback.next_scan();
    ASSERT_EQ(scan.size(), kBeams);
    for (std::size_t b = 0; b < kBeams; ++b) {
      if (recorded_no_echo(k, b)) {
        EXPECT_EQ(scan[b].status, ReadingStatus::NoEcho) << "scan " << k << " beam " << b;
      } else {
        EXPECT_EQ(scan[b].status, ReadingStatus::Valid) << "scan " << k << " beam " << b;
        EXPECT_EQ(scan[b].range_mm, recorded_range_mm(k, b)) << "scan " << k << " beam " << b;
      }
    }
  }
  EXPECT_EQ(playback.next_scan_time(), std::nullopt);
  EXPECT_THROW(playback.next_scan(), core::Error);
  EXPECT_EQ(playback.time_s(), 0.0);  // taking scans does not move the clock
}

TEST(RecordingPlayback, CaseReadingIsTheLatestAtOrBeforeNow) {
  RecordingPlayback playback(recording(), "run.csv");
  EXPECT_EQ(playback.read_case_sensor(), 22.5);
  playback.advance_to(0.149);
  EXPECT_EQ(playback.read_case_sensor(), 22.5);
  playback.advance_to(0.15);
  EXPECT_EQ(playback.read_case_sensor(), 22.75);
  playback.advance_to(0.7);
  EXPECT_EQ(playback.read_case_sensor(), 23.0);
  playback.advance_to(1.2);
  EXPECT_EQ(playback.read_case_sensor(), 23.25);
  playback.advance_to(9.0);
  EXPECT_EQ(playback.read_case_sensor(), 23.5);
  EXPECT_THROW(playback.advance_to(1.0), core::InvalidInput);
}

TEST(RecordingPlayback, BeforeTheFirstReadingTheFirstOneAndThePowerOn) {
  io::MeasurementTableBuilder builder;
  for (const auto& m : io::recording_metadata(kBeams, 0.0, 0.5)) {
    builder.add_metadata(m.key, m.value);
  }
  builder.append({.time_s = 2.0, .range_mm = 1500.0, .beam = 3});
  builder.append({.time_s = 2.5, .case_temp_c = 30.25});
  RecordingPlayback playback(builder.finish(), "late.csv");
  EXPECT_EQ(playback.time_s(), 2.0);  // the clock starts at the first row
  EXPECT_EQ(playback.read_case_sensor(), 30.25);
  EXPECT_TRUE(playback.power_on());  // no power row: on
}

TEST(RecordingPlayback, PowerStateFollowsThePowerRows) {
  RecordingPlayback playback(recording(), "run.csv");
  EXPECT_TRUE(playback.power_on());
  playback.advance_to(0.29);
  EXPECT_TRUE(playback.power_on());
  playback.advance_to(0.3);
  EXPECT_FALSE(playback.power_on());
  playback.advance_to(0.99);
  EXPECT_FALSE(playback.power_on());
  playback.advance_to(1.0);
  EXPECT_TRUE(playback.power_on());
}

TEST(RecordingPlayback, StepsFromEventToEventToTheEnd) {
  RecordingPlayback playback(recording(), "run.csv");
  std::vector<double> events;
  while (const std::optional<double> t = playback.next_event_time()) {
    ASSERT_LT(events.size(), 100u) << "the events never end";
    events.push_back(*t);
    playback.advance_to(*t);
    if (playback.next_scan_time() == playback.time_s()) playback.next_scan();
  }
  EXPECT_EQ(events, (std::vector<double>{0.0, 0.1, 0.15, 0.2, 0.3, 0.6, 1.0, 1.1, 1.15, 1.2, 1.5}));
  EXPECT_TRUE(playback.finished());
  EXPECT_EQ(playback.time_s(), 1.5);
  EXPECT_EQ(playback.next_scan_time(), std::nullopt);
}

// The case readings and power changes come out in file order relative to the scans: those
// before a scan when the clock reaches them, those after it (even at its very time) only once
// it was played.
TEST(RecordingPlayback, PlayedEventsKeepTheirOrderAroundTheScans) {
  io::MeasurementTableBuilder builder;
  for (const auto& m : io::recording_metadata(kBeams, 0.0, 0.5)) {
    builder.add_metadata(m.key, m.value);
  }
  builder.append({.time_s = 0.0, .case_temp_c = 22.5});
  builder.append({.time_s = 0.0, .power = true});
  append_scan(builder, 0, kBeams);                        // at 0.0
  builder.append({.time_s = 0.0, .case_temp_c = 22.75});  // after it, at its time
  append_scan(builder, 1, kBeams);                        // at 0.1
  builder.append({.time_s = 0.15, .power = false});
  RecordingPlayback playback(builder.finish(), "order.csv");

  std::vector<RecordingPlayback::Event> before = playback.take_played_events();
  ASSERT_EQ(before.size(), 2u);
  EXPECT_EQ(before[0].case_c, 22.5);
  EXPECT_EQ(before[1].power, true);
  EXPECT_TRUE(playback.take_played_events().empty());  // the reading at 0.0 waits for scan 0
  playback.next_scan();
  const auto after = playback.take_played_events();
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].case_c, 22.75);
  EXPECT_EQ(after[0].time_s, 0.0);
  playback.advance_to(0.1);
  playback.next_scan();
  EXPECT_TRUE(playback.take_played_events().empty());  // the power change is at 0.15
  playback.advance_to(0.15);
  const auto last = playback.take_played_events();
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].power, false);
  EXPECT_TRUE(playback.finished());
}

// Measured data with no geometry lines (another logger's, or the twin's CSV) plays with the
// beams its rows name: the highest beam index + 1.
TEST(RecordingPlayback, MeasuredDataWithoutGeometryHasTheBeamsItsRowsName) {
  io::MeasurementTable no_geometry = recording();
  no_geometry.metadata.clear();
  EXPECT_EQ(RecordingPlayback(no_geometry, "measured.csv").beams(), kBeams);
  io::MeasurementTable fewer = recording(kBeams - 2);
  fewer.metadata.clear();
  EXPECT_EQ(RecordingPlayback(fewer, "measured.csv").beams(), kBeams - 2);
}

TEST(RecordingPlayback, BadRecordingsAreRefusedNamingWhereAndWhat) {
  const auto message_of = [](const io::MeasurementTable& table) {
    try {
      RecordingPlayback playback(table, "bad.csv");
    } catch (const core::InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // A beam outside the geometry, on line 7 of the file (4 metadata lines, the header, a row).
  std::istringstream file(
      "# sensor: LMS200\n# beams: 361\n# start_angle_deg: 0\n# resolution_deg: 0.5\n"
      "time_s,range_mm,beam,case_temp_c\n0,,,22.5\n0,1000,361,\n");
  const std::string beam_outside = message_of(io::read_measured_data(file, "bad.csv"));
  EXPECT_NE(beam_outside.find("bad.csv:7"), std::string::npos) << beam_outside;
  EXPECT_NE(beam_outside.find("beam 361"), std::string::npos) << beam_outside;

  // Some of the geometry lines but not all: a damaged header, not measured data.
  io::MeasurementTable part_geometry = recording();
  std::erase_if(part_geometry.metadata,
                [](const io::MetadataLine& m) { return m.key == io::kRecordingResolutionKey; });
  const std::string part = message_of(part_geometry);
  EXPECT_NE(part.find("bad.csv: an incomplete recording geometry"), std::string::npos) << part;
  EXPECT_NE(part.find("missing '# resolution_deg'"), std::string::npos) << part;

  io::MeasurementTable no_scan = recording();
  std::erase_if(no_scan.rows, [](const io::MeasurementRow& r) { return r.range_mm.has_value(); });
  EXPECT_NE(message_of(no_scan).find("no scan"), std::string::npos) << message_of(no_scan);

  io::MeasurementTable no_case = recording();
  std::erase_if(no_case.rows,
                [](const io::MeasurementRow& r) { return r.case_temp_c.has_value(); });
  EXPECT_NE(message_of(no_case).find("case_temp_c"), std::string::npos) << message_of(no_case);

  io::MeasurementTable twice = recording();
  twice.rows.insert(twice.rows.begin() + 2, twice.rows[1]);  // beam 1 of scan 0 again
  EXPECT_NE(message_of(twice).find("appears twice"), std::string::npos) << message_of(twice);
}

// ---- the emulator playing the recording to the host driver over a real pty ----

namespace test = tofcomp::test;

// The codes the device sends for recorded scan k in millimetres: the range, or the reserved
// "beyond maximum" code of the 8 m mode (13 bits all ones, minus 8) for a beam with no echo.
std::vector<std::uint16_t> recorded_codes(std::size_t k) {
  std::vector<std::uint16_t> codes;
  for (std::size_t b = 0; b < kBeams; ++b) {
    codes.push_back(recorded_no_echo(k, b) ? std::uint16_t{0x1FFF - 8}
                                           : static_cast<std::uint16_t>(recorded_range_mm(k, b)));
  }
  return codes;
}

EmulatorSettings playing(double time_scale) {
  EmulatorSettings s;
  s.scenario = test::default_scenario();
  s.time_scale = time_scale;
  s.recording = recording();
  s.recording_source = "run.csv";
  return s;
}

test::lms::DriverSettings host_driver() {
  test::lms::DriverSettings d;
  d.baud = 500000;
  d.ack_timeout = 100ms;
  d.scan_timeout = 500ms;  // the power gap: the device comes back at 9600 Bd, unheard
  return d;
}

// Waits until the emulator has played its recording to the end; false after `limit`.
bool wait_for_playback_end(const test::LinkHarness& link, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!link.emulator_counters().playback_finished) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

TEST(EmulatorPlayingARecording, DeliversExactlyTheRecordedScansInOrderThroughThePowerGap) {
  test::LinkHarness link(playing(0.0), host_driver());
  link.start();
  ASSERT_TRUE(link.wait_for_scans(kScans, 25s)) << "fewer than " << kScans << " scans arrived";
  ASSERT_TRUE(wait_for_playback_end(link, 10s));
  const EmulatorCounters counters = link.emulator_counters();
  EXPECT_EQ(counters.scans_sent, kScans);
  EXPECT_EQ(counters.failure, "");
  link.stop();
  // The device went off and came back at the power-on rate: the host had to bring it up again.
  EXPECT_GE(link.driver_counters().bring_ups, 2u);
  ASSERT_EQ(link.received().size(), kScans);  // and nothing after the end
  for (std::size_t k = 0; k < kScans; ++k) {
    EXPECT_EQ(link.received()[k].codes, recorded_codes(k)) << "scan " << k;
  }
}

TEST(EmulatorPlayingARecording, CaseSensorPowerAndClockAnswerFromTheRecording) {
  Emulator emulator(playing(0.0));
  EXPECT_EQ(emulator.read_case_sensor(), 22.5);
  EXPECT_EQ(emulator.twin_time_s(), 0.0);
  emulator.start();
  // No host reads: the first scan waits for one, and the clock stays at its time.
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(emulator.twin_time_s(), 0.0);
  EXPECT_EQ(emulator.read_case_sensor(), 22.5);
  EXPECT_TRUE(emulator.power_on());
  EXPECT_FALSE(emulator.counters().playback_finished);
  emulator.stop();
}

TEST(EmulatorPlayingARecording, PlaysToTheEndInScaledTimeAndKeepsTheRecordedValues) {
  constexpr double kScale = 2.0;  // 1.5 recorded seconds in 0.75 s
  const auto started = std::chrono::steady_clock::now();
  test::LinkHarness link(playing(kScale), host_driver());
  link.start();
  ASSERT_TRUE(wait_for_playback_end(link, 20s));
  EXPECT_GE(std::chrono::steady_clock::now() - started,
            std::chrono::duration<double>(1.5 / kScale));
  link.stop();
  // Scans due before the host streamed are not sent; those delivered are recorded ones, in order.
  std::size_t next = 0;
  for (const auto& got : link.received()) {
    while (next < kScans && recorded_codes(next) != got.codes) ++next;
    ASSERT_LT(next, kScans) << "a delivered scan is not a recorded one, or out of order";
    ++next;
  }
}

TEST(EmulatorPlayingARecording, WithNoHostPlaysToTheEndAndAnswersWithTheLastRecordedState) {
  Emulator emulator(playing(4.0));  // 1.5 recorded seconds in 0.375 s
  emulator.start();
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (!emulator.counters().playback_finished && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_TRUE(emulator.counters().playback_finished);
  EXPECT_EQ(emulator.twin_time_s(), 1.5);
  EXPECT_EQ(emulator.read_case_sensor(), 23.5);
  EXPECT_TRUE(emulator.power_on());
  EXPECT_EQ(emulator.counters().scans_sent, 0u);  // no host ever asked for scans
  emulator.stop();
}

// Holding recorded scans for the host: every recorded scan reaches it, even those due while it
// was still bringing the link up, and the observer hears every reading, power change and scan
// in the recording's order, each scan with its recorded time and ranges.
TEST(EmulatorPlayingARecording, HoldingScansDeliversEveryOneAndReportsEventsInOrder) {
  EmulatorSettings settings = playing(4.0);  // 1.5 recorded seconds in 0.375 s, if not held
  settings.hold_recorded_scans = true;
  std::mutex mutex;
  std::vector<PlaybackEvent> events;
  test::LinkHarness link(settings, host_driver(), [&](Emulator& emulator) {
    emulator.on_playback_event([&](const PlaybackEvent& e) {
      std::lock_guard lock(mutex);
      events.push_back(e);
    });
  });
  link.start();
  ASSERT_TRUE(link.wait_for_scans(kScans, 25s)) << "fewer than " << kScans << " scans arrived";
  ASSERT_TRUE(wait_for_playback_end(link, 10s));
  link.stop();
  ASSERT_EQ(link.received().size(), kScans);
  for (std::size_t k = 0; k < kScans; ++k) {
    EXPECT_EQ(link.received()[k].codes, recorded_codes(k)) << "scan " << k;
  }
  // The recording's rows in file order, one event per reading, power change and scan.
  const io::MeasurementTable table = recording();
  std::vector<double> expected_times;
  std::vector<char> expected_kinds;
  double last_scan = -1.0;
  for (const auto& row : table.rows) {
    if (row.range_mm) {
      if (row.time_s == last_scan) continue;  // the scan's other beams
      last_scan = row.time_s;
      expected_kinds.push_back('s');
    } else {
      last_scan = -1.0;
      expected_kinds.push_back(row.power ? 'p' : 'c');
    }
    expected_times.push_back(row.time_s);
  }
  std::lock_guard lock(mutex);
  ASSERT_EQ(events.size(), expected_kinds.size());
  std::size_t scan = 0;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const char kind = !events[i].scan_ranges_mm.empty() ? 's' : events[i].power ? 'p' : 'c';
    EXPECT_EQ(kind, expected_kinds[i]) << "event " << i;
    EXPECT_EQ(events[i].time_s, expected_times[i]) << "event " << i;
    if (kind != 's') continue;
    ASSERT_EQ(events[i].scan_ranges_mm.size(), kBeams);
    for (std::size_t b = 0; b < kBeams; ++b) {
      if (recorded_no_echo(scan, b)) {
        EXPECT_TRUE(std::isnan(events[i].scan_ranges_mm[b]));
      } else {
        EXPECT_EQ(events[i].scan_ranges_mm[b], recorded_range_mm(scan, b));
      }
    }
    ++scan;
  }
  EXPECT_EQ(scan, kScans);
}

TEST(EmulatorPlayingARecording, RefusesARecordingNoVariantCarries) {
  EmulatorSettings settings = playing(0.0);
  settings.recording = recording(100);  // 100 beams: no LMS 200 variant sends 100 values
  try {
    Emulator emulator(settings);
    ADD_FAILURE() << "a 100-beam recording was accepted";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("run.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("100 beams"), std::string::npos) << e.what();
  }
  settings.recording = recording(kBeams);
  EXPECT_NO_THROW(Emulator emulator(settings));
}

}  // namespace
}  // namespace tofcomp::sim::lms200
