#include "realtime/recording_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "io/measured_data_csv.hpp"
#include "io/measurement_table_builder.hpp"
#include "tests/realtime/realtime_examples.hpp"

namespace tofcomp::realtime {
namespace {

bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_identical(const ipc::CompensatedScan& a, const ipc::CompensatedScan& b) {
  ASSERT_EQ(a.sequence, b.sequence);
  ASSERT_EQ(a.beams.size(), b.beams.size());
  EXPECT_TRUE(same(a.junction_c, b.junction_c)) << a.sequence;
  EXPECT_TRUE(same(a.junction_std_c, b.junction_std_c)) << a.sequence;
  for (std::size_t i = 0; i < a.beams.size(); ++i) {
    const ipc::BeamValue& x = a.beams[i];
    const ipc::BeamValue& y = b.beams[i];
    EXPECT_EQ(x.flags, y.flags) << a.sequence << " beam " << i;
    EXPECT_TRUE(same(x.raw_mm, y.raw_mm) || (std::isnan(x.raw_mm) && std::isnan(y.raw_mm)));
    EXPECT_TRUE(same(x.compensated_mm, y.compensated_mm) ||
                (std::isnan(x.compensated_mm) && std::isnan(y.compensated_mm)))
        << a.sequence << " beam " << i;
    EXPECT_TRUE(same(x.window_mm, y.window_mm) ||
                (std::isnan(x.window_mm) && std::isnan(y.window_mm)))
        << a.sequence << " beam " << i;
    EXPECT_EQ(x.mode_posterior, y.mode_posterior);
  }
}

// A session as the daemon lives it (case readings at 1 Hz while heating, scans at 20 Hz on
// five beams with an occasional missing echo, the power cut and restored), recorded row by row
// into the interchange CSV, written to a file, read back and replayed: the replay gives the
// very numbers the live pipeline gave.
TEST(RecordingReplay, ReplayEqualsTheLivePipeline) {
  const auto calibration = std::make_shared<core::Calibration>(testing::round_calibration());
  CompensationPipeline live;
  live.set_calibration(calibration, 1);
  io::MeasurementTableBuilder recording;
  for (const auto& m : io::recording_metadata(5, -90.0, 45.0))
    recording.add_metadata(m.key, m.value);

  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<ipc::CompensatedScan> outputs;
  std::vector<io::MeasurementRow> rows;
  std::uint64_t device_sequence = 0;
  for (int tick = 0; tick < 20 * 120; ++tick) {
    const double t = 1000.0 + tick * 0.05 + 1e-7 * (tick % 7);  // irregular, like a host clock
    if (tick == 20 * 60) {
      live.on_power(t, false);
      rows.push_back({.time_s = t, .power = false});
    }
    if (tick == 20 * 70) {
      live.on_power(t, true);
      rows.push_back({.time_s = t, .power = true});
    }
    if (tick % 20 == 0) {
      const double case_c = 30.0 + 0.01 * tick / 20 + 0.0625 * std::round(noise(rng));
      live.on_case_reading(t, case_c);
      rows.push_back({.time_s = t, .case_temp_c = case_c});
    }
    const bool on = tick < 20 * 60 || tick >= 20 * 70;
    if (!on) continue;
    RawScan scan;
    scan.device_sequence = device_sequence++;
    scan.time_s = t;
    scan.start_angle_deg = -90.0;
    scan.resolution_deg = 45.0;
    for (int b = 0; b < 5; ++b) {
      scan.ranges_mm.push_back(std::round(2000.0 + 100.0 * b + 18.0 + 2.0 * noise(rng)));
      scan.no_echo.push_back(tick % 37 == b ? 1 : 0);
    }
    outputs.push_back(live.on_scan(scan));
    io::append_scan_rows(scan.time_s, scan.ranges_mm, scan.no_echo, rows);
  }
  for (const auto& row : rows) recording.append(row);
  const auto file = std::filesystem::temp_directory_path() /
                    ("tofcomp-replay-" + std::to_string(::getpid()) + ".csv");
  io::write_measured_data_file(file.string(), recording.finish());
  const io::MeasurementTable table = io::read_measured_data_file(file.string());
  std::filesystem::remove(file);

  CompensationPipeline replay;
  replay.set_calibration(calibration, 1);
  std::vector<ipc::CompensatedScan> replayed;
  replay_recording(table, file.string(), replay,
                   [&](const ipc::CompensatedScan& s) { replayed.push_back(s); });
  ASSERT_EQ(replayed.size(), outputs.size());
  for (std::size_t i = 0; i < outputs.size(); ++i) expect_identical(outputs[i], replayed[i]);
  // The session did exercise what it claims to.
  EXPECT_EQ(outputs.back().beams.size(), 5u);
  EXPECT_FALSE(std::isnan(outputs.back().beams[0].window_mm));
  EXPECT_DOUBLE_EQ(replayed.back().start_angle_deg, -90.0);
  EXPECT_DOUBLE_EQ(replayed.back().resolution_deg, 45.0);
}

TEST(RecordingReplay, NamesWhatIsWrongWithARecording) {
  CompensationPipeline pipeline;
  io::MeasurementTableBuilder part;
  part.add_metadata(io::kRecordingBeamsKey, "3");
  part.add_metadata(io::kRecordingStartAngleKey, "0");
  part.append({.time_s = 0.0, .range_mm = 1000.0});
  try {
    replay_recording(part.finish(), "part.csv", pipeline, [](const ipc::CompensatedScan&) {});
    FAIL() << "a file with part of the geometry was replayed";
  } catch (const core::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("part.csv: an incomplete recording geometry"), std::string::npos) << what;
    EXPECT_NE(what.find("missing '# resolution_deg'"), std::string::npos) << what;
  }
  io::MeasurementTableBuilder outside;
  for (const auto& m : io::recording_metadata(3, 0.0, 1.0)) outside.add_metadata(m.key, m.value);
  outside.append({.time_s = 0.0, .range_mm = 1000.0, .beam = 3});
  try {
    replay_recording(outside.finish(), "outside.csv", pipeline, [](const ipc::CompensatedScan&) {});
    FAIL() << "a beam outside the geometry was replayed";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("beam 3 outside the recording's 3 beams"),
              std::string::npos)
        << e.what();
  }
}

// Measured data in the interchange CSV as another logger writes it (no geometry lines, ranges
// of two beams at their own times, a case reading now and then, a beam ranged twice at one
// time) replays as the same rows under a recording's geometry lines would: the same scans, bit
// for bit, with the angles unknown (NaN) instead of the declared ones. Nothing is written over:
// the beam ranged twice gives two scans.
TEST(RecordingReplay, MeasuredDataReplaysAsTheRecordingOfItsRows) {
  const auto calibration = std::make_shared<core::Calibration>(testing::round_calibration());
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<io::MeasurementRow> rows;
  std::size_t range_rows = 0;
  for (int tick = 0; tick < 4 * 600; ++tick) {
    const double t = 0.25 * tick;
    if (tick % 4 == 0) rows.push_back({.time_s = t, .case_temp_c = 30.0 + 0.002 * tick});
    for (int b = 0; b < 2; ++b) {
      const double range = std::round(3000.0 + 500.0 * b + 17.0 + 2.0 * noise(rng));
      rows.push_back({.time_s = t + 0.001 * b, .range_mm = range, .beam = b});
      ++range_rows;
    }
    if (tick == 1000) {  // beam 1 ranged again at the same time_s (ties are allowed)
      rows.push_back({.time_s = rows.back().time_s, .range_mm = 3519.0, .beam = 1});
      ++range_rows;
    }
  }
  const auto replay = [&](bool with_geometry) {
    io::MeasurementTableBuilder table;
    if (with_geometry) {
      for (const auto& m : io::recording_metadata(2, -10.0, 20.0))
        table.add_metadata(m.key, m.value);
    }
    for (const auto& row : rows) table.append(row);
    CompensationPipeline pipeline;
    pipeline.set_calibration(calibration, 1);
    std::vector<ipc::CompensatedScan> scans;
    replay_recording(table.finish(), "measured.csv", pipeline,
                     [&](const ipc::CompensatedScan& s) { scans.push_back(s); });
    return scans;
  };
  const std::vector<ipc::CompensatedScan> recording = replay(true);
  const std::vector<ipc::CompensatedScan> measured = replay(false);
  ASSERT_EQ(measured.size(), recording.size());
  for (std::size_t i = 0; i < measured.size(); ++i) expect_identical(recording[i], measured[i]);
  EXPECT_TRUE(std::isnan(measured.back().start_angle_deg));
  EXPECT_TRUE(std::isnan(measured.back().resolution_deg));
  EXPECT_DOUBLE_EQ(recording.back().start_angle_deg, -10.0);
  // Every range row is a beam of one scan: one scan per row here (the two beams' times differ).
  ASSERT_EQ(measured.size(), range_rows);
  std::size_t compensated = 0;
  for (const auto& scan : measured) {
    ASSERT_EQ(scan.beams.size(), 2u);
    for (const auto& beam : scan.beams) compensated += std::isfinite(beam.compensated_mm) ? 1 : 0;
  }
  // The junction filter needs its first case reading before a range is compensated; from there
  // on every range is.
  EXPECT_GE(compensated, range_rows - 2);
}

}  // namespace
}  // namespace tofcomp::realtime
