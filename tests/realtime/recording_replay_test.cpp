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
  io::MeasurementTableBuilder plain;
  plain.append({.time_s = 0.0, .range_mm = 1000.0});
  try {
    replay_recording(plain.finish(), "plain.csv", pipeline, [](const ipc::CompensatedScan&) {});
    FAIL() << "a file without the geometry was replayed";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("plain.csv: not a tofcompd recording"), std::string::npos)
        << e.what();
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

}  // namespace
}  // namespace tofcomp::realtime
