// The recorder in a directory another user may write to, and on a disk that fills: it never
// writes through a symlink or over a file planted there, a calibration run's named file replaces
// what is there by a rename, and a failed write names the system's error and leaves the file
// cut at its last whole scan, so that it still reads.
#include "daemon/recorder.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "io/measured_data_csv.hpp"
#include "tests/support/file_text.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::daemon {
namespace {

constexpr std::size_t kBeams = 181;
const std::string kPrecious = "a file the daemon must not touch\n";

realtime::RawScan scan_at(double time_s) {
  realtime::RawScan scan;
  scan.time_s = time_s;
  scan.start_angle_deg = 0.0;
  scan.resolution_deg = 1.0;
  scan.ranges_mm.assign(kBeams, 3000.0);
  scan.no_echo.assign(kBeams, 0);
  return scan;
}

// The name the recorder gives a rotation's file opened at `t` (UTC, to the second).
std::string stamped_name(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", &tm);
  return std::string("tofcompd-") + text + ".csv";
}

TEST(Recorder, ARotationsFileIsNeverOpenedThroughAPlantedSymlink) {
  test::TemporaryDirectory dir("tofcomp-recorder");
  test::TemporaryDirectory elsewhere("tofcomp-elsewhere");
  const std::filesystem::path target = elsewhere.path() / "precious.txt";
  std::ofstream(target) << kPrecious;
  // Every name the next few seconds could give, planted ahead as symlinks to the target.
  const std::time_t now = std::time(nullptr);
  for (std::time_t t = now - 1; t <= now + 10; ++t) {
    std::filesystem::create_symlink(target, dir.path() / stamped_name(t));
  }
  {
    Recorder recorder(
        {.directory = dir.path(), .max_rows = std::nullopt, .max_minutes = std::nullopt});
    recorder.case_reading(0.0, 30.0);
    recorder.scan(scan_at(0.1));
    const std::filesystem::path file = recorder.current_file();
    EXPECT_FALSE(std::filesystem::is_symlink(file)) << file;
    EXPECT_NE(file.filename().string().find("-1.csv"), std::string::npos) << file;
    EXPECT_EQ(io::read_measured_data_file(file).rows.size(), 1 + kBeams);
  }
  EXPECT_EQ(testing::file_text(target), kPrecious);
}

TEST(Recorder, ANamedFileReplacesAPlantedSymlinkNotItsTarget) {
  test::TemporaryDirectory dir("tofcomp-recorder");
  test::TemporaryDirectory elsewhere("tofcomp-elsewhere");
  const std::filesystem::path target = elsewhere.path() / "precious.txt";
  std::ofstream(target) << kPrecious;
  const std::filesystem::path named = dir.path() / "power_cycle_run.recording";
  std::filesystem::create_symlink(target, named);
  {
    Recorder recorder({.directory = dir.path(),
                       .max_rows = std::nullopt,
                       .max_minutes = std::nullopt,
                       .file_name = named.filename()});
    recorder.case_reading(0.0, 30.0);
    recorder.scan(scan_at(0.1));
  }
  EXPECT_EQ(testing::file_text(target), kPrecious);
  EXPECT_FALSE(std::filesystem::is_symlink(named));
  EXPECT_EQ(io::read_measured_data_file(named).rows.size(), 1 + kBeams);
  // Nothing but the recording is left beside it (no temporary file).
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                          std::filesystem::directory_iterator()),
            1);
}

// A file that cannot grow (here the file-size limit, RLIMIT_FSIZE, as a full disk would): the
// error names the system's reason, and the file keeps its whole scans only. Once there is room
// again, the recording goes on in a new file that starts with the pipeline's state.
TEST(Recorder, AFailedWriteNamesTheErrorCutsTheFileAtItsLastWholeScanAndRecordingResumes) {
  test::TemporaryDirectory dir("tofcomp-recorder");
  constexpr rlim_t kLimitBytes = 40000;  // a few scans of 181 rows
  std::filesystem::path file;
  std::filesystem::path resumed;
  std::string message;
  {
    Recorder recorder(
        {.directory = dir.path(), .max_rows = std::nullopt, .max_minutes = std::nullopt});
    recorder.case_reading(0.0, 30.0);
    recorder.scan(scan_at(0.1));  // opens the file before the limit
    file = recorder.current_file();
    const auto previous_handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit previous{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &previous), 0);
    rlimit limit = previous;
    limit.rlim_cur = kLimitBytes;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
    double t = 0.1;
    try {
      for (int i = 1; i < 1000; ++i) recorder.scan(scan_at(t += 0.0133));
    } catch (const core::Error& e) {
      message = e.what();
    }
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &previous), 0);
    std::signal(SIGXFSZ, previous_handler);
    EXPECT_TRUE(recorder.suspended());
    // Within the retry interval nothing is tried: the scans are counted lost.
    const std::uint64_t lost = recorder.counters().scans_lost;
    recorder.case_reading(t + 1.0, 31.0);
    recorder.scan(scan_at(t + 1.0));
    EXPECT_EQ(recorder.counters().scans_lost, lost + 1);
    EXPECT_EQ(recorder.current_file(), file);
    recorder.scan(scan_at(t + kRecorderRetryAfterS + 0.5));
    EXPECT_FALSE(recorder.suspended());
    resumed = recorder.current_file();
  }
  ASSERT_NE(resumed, file);
  const io::MeasurementTable again = io::read_measured_data_file(resumed);
  ASSERT_EQ(again.rows.size(), 1 + kBeams);
  ASSERT_TRUE(again.rows.front().case_temp_c.has_value());
  EXPECT_EQ(*again.rows.front().case_temp_c, 31.0);  // the last reading, taken while suspended
  EXPECT_NE(message.find("recording: cannot write " + file.string() + ": File too large"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("the file ends at its last whole scan"), std::string::npos) << message;
  EXPECT_LE(std::filesystem::file_size(file), kLimitBytes);
  const io::MeasurementTable table = io::read_measured_data_file(file);
  // The case reading, then whole scans only.
  ASSERT_GT(table.rows.size(), 1 + kBeams);
  EXPECT_EQ((table.rows.size() - 1) % kBeams, 0u) << table.rows.size();
}

}  // namespace
}  // namespace tofcomp::daemon
