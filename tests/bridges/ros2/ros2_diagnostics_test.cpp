// The scanner's health as a DiagnosticStatus (bridges/ros2/scanner_diagnostics.hpp): the levels
// from the daemon's status and the scans' flags, and the values as the status and the latest
// scan give them.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "bridges/ros2/scanner_diagnostics.hpp"

namespace tofcomp::bridges::ros2 {
namespace {

nlohmann::json status(const std::string& link, int calibration_id) {
  return {{"device", "emulated LMS 200"},
          {"link", link},
          {"state", "publishing compensated scans"},
          {"calibration", {{"id", calibration_id}, {"extension", nullptr}}}};
}

// A scan of 10 beams, the first `flagged` with `flag`.
client::Scan scan(std::uint64_t sequence, int flagged, std::uint16_t flag) {
  client::Scan s;
  s.info.sequence = sequence;
  s.info.junction_c = 26.25;
  s.info.junction_std_c = 0.125;
  s.info.case_c = 24.5;
  for (int i = 0; i < 10; ++i) {
    client::Beam b{};
    b.flags = i < flagged ? flag : 0;
    s.beams.push_back(b);
  }
  return s;
}

std::map<std::string, std::string> values_of(const DiagnosticValues& d) {
  return {d.values.begin(), d.values.end()};
}

constexpr const char* kStreaming = "streaming: streaming at 500000 Bd";

TEST(Ros2Diagnostics, ValuesComeFromTheStatusAndTheLatestScan) {
  FlaggedBeams beams;
  beams.add(scan(7, 1, TOFCOMP_FLAG_OUTLIER));
  beams.add(scan(8, 3, TOFCOMP_FLAG_NO_ECHO));
  const DiagnosticValues d = scanner_diagnostics(status(kStreaming, 2), scan(8, 0, 0).info, beams, "/s.sock");
  EXPECT_EQ(d.level, DiagnosticLevel::Ok);
  EXPECT_EQ(d.name, "tofcompd: /s.sock");
  EXPECT_EQ(d.hardware_id, "emulated LMS 200");
  EXPECT_EQ(d.message, "publishing compensated scans");
  auto v = values_of(d);
  EXPECT_EQ(v["junction temperature (°C)"], "26.25");
  EXPECT_EQ(v["junction temperature std (°C)"], "0.125");
  EXPECT_EQ(v["case temperature (°C)"], "24.5");
  EXPECT_EQ(v["scan"], "8");
  EXPECT_EQ(v["calibration id"], "2");
  EXPECT_EQ(v["calibration extension"], "none");
  EXPECT_EQ(v["link"], kStreaming);
  EXPECT_EQ(v["flagged beams"], "1");  // the outlier; no echo is counted apart
  EXPECT_EQ(v["beams without echo"], "3");
  EXPECT_EQ(v["beams"], "20");
  EXPECT_EQ(v["flagged beams (share)"], "0.05");
  EXPECT_EQ(v["scans"], "2");
  EXPECT_EQ(v["first scan"], "7");
  EXPECT_EQ(v["last scan"], "8");
}

TEST(Ros2Diagnostics, LevelsSayWhatIsWrong) {
  FlaggedBeams some;
  some.add(scan(1, 0, 0));
  const auto latest = scan(1, 0, 0).info;
  EXPECT_EQ(scanner_diagnostics(status("lost: no answer", 1), latest, some, "s").level,
            DiagnosticLevel::Error);
  EXPECT_EQ(scanner_diagnostics(status(kStreaming, 1), latest, FlaggedBeams(), "s").level,
            DiagnosticLevel::Stale);
  EXPECT_EQ(scanner_diagnostics(status(kStreaming, 0), latest, some, "s").level,
            DiagnosticLevel::Warn);
  FlaggedBeams many;
  many.add(scan(2, 3, TOFCOMP_FLAG_TEMPERATURE_STALE));  // 30 % > kWarnFlaggedShare
  const DiagnosticValues warned = scanner_diagnostics(status(kStreaming, 1), latest, many, "s");
  EXPECT_EQ(warned.level, DiagnosticLevel::Warn);
  EXPECT_EQ(warned.message, "flagged beams: 0.3");
  EXPECT_EQ(unreachable_diagnostics("s", "connect: refused").level, DiagnosticLevel::Error);
  EXPECT_EQ(values_of(scanner_diagnostics(status(kStreaming, 1), std::nullopt, some, "s"))["scan"],
            "none");
}

}  // namespace
}  // namespace tofcomp::bridges::ros2
