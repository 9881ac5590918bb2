// Relative paths are resolved against the configuration file's directory (or the base given to
// parse_daemon_config); absolute ones are kept; GPIO chips and shm names are not paths.
#include <unistd.h>

#include <fstream>

#include "config_test_support.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::settings {
namespace {

namespace fs = std::filesystem;

const std::string kPaths =
    "emulator: {enabled: true, scenario: scenarios/s.yaml, link: run/lms200}\n"
    "case_sensor: {backend: simulated}\n"
    "power: {sense: {chip: gpiochip0, line: SENSE}}\n"
    "calibration: {file: ../shared/calibration.yaml}\n"
    "outputs: {socket: {path: tofcompd.sock}, shm: {name: /tofcompd-test}}\n"
    "recording: {directory: ./recordings/}\n"
    "recalibration: {source: recording, datasheet: /opt/lms/datasheet.yaml,"
    " recording: {data: data/run.csv}}\n";

void expect_resolved_against(const DaemonConfig& c, const fs::path& dir) {
  EXPECT_EQ(c.emulator.scenario, dir / "scenarios" / "s.yaml");
  EXPECT_EQ(c.emulator.link, dir / "run" / "lms200");
  EXPECT_EQ(c.link.device, dir / "run" / "lms200");  // the emulator's link
  EXPECT_EQ(c.calibration.file, dir.parent_path() / "shared" / "calibration.yaml");
  EXPECT_EQ(c.recalibration.output, c.calibration.file);
  EXPECT_EQ(c.outputs.socket.path, dir / "tofcompd.sock");
  EXPECT_EQ(c.recording.directory, dir / "recordings" / "");
  EXPECT_EQ(c.recalibration.data, dir / "data" / "run.csv");
  EXPECT_EQ(c.recalibration.datasheet, "/opt/lms/datasheet.yaml");  // absolute: kept
  EXPECT_EQ(c.power.sense->chip, "gpiochip0");                      // not a path
  EXPECT_EQ(c.outputs.shm.name, "/tofcompd-test");
}

TEST(ConfigPaths, ResolvedAgainstTheFilesDirectory) {
  const test::TemporaryDirectory temporary{"tofcompd-config"};
  const fs::path dir = temporary.path() / "etc";
  fs::create_directories(dir);
  std::ofstream(dir / "tofcompd.yaml") << kPaths;
  const DaemonConfig c = load_daemon_config(dir / "tofcompd.yaml");
  expect_resolved_against(c, dir);
}

TEST(ConfigPaths, ResolvedAgainstTheBaseGiven) {
  const DaemonConfig c = parse_daemon_config(kPaths, "test.yaml", "/srv/tofcompd/conf");
  expect_resolved_against(c, "/srv/tofcompd/conf");
}

TEST(ConfigPaths, ResolvedAgainstTheCurrentDirectoryWithoutABase) {
  const DaemonConfig c = parse_daemon_config(kPaths, "test.yaml");
  expect_resolved_against(c, fs::current_path());
}

TEST(ConfigPaths, FileNamedRelativelyIsReadFromItsDirectory) {
  const test::TemporaryDirectory temporary{"tofcompd-config"};
  std::ofstream(temporary.path() / "tofcompd.yaml") << kPaths;
  const fs::path previous = fs::current_path();
  fs::current_path(temporary.path().parent_path());
  DaemonConfig c;
  try {
    c = load_daemon_config(temporary.path().filename() / "tofcompd.yaml");
  } catch (...) {
    fs::current_path(previous);
    throw;
  }
  fs::current_path(previous);
  EXPECT_EQ(c.source, (temporary.path().filename() / "tofcompd.yaml").string());
  expect_resolved_against(c, temporary.path());
}

TEST(ConfigPaths, EmptyPathIsAnError) {
  const std::string message = testing::error_of(testing::kMinimal + "calibration: {file: \"\"}\n");
  EXPECT_NE(message.find("test.yaml: calibration.file must be a path, not empty"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace tofcomp::settings
