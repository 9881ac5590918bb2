// tofcompd end to end: the real binary on its emulated LMS 200 (a real pty) and simulated case
// sensor, read by a socket subscriber and a shared-memory reader; its recording replayed
// offline through the compensation path gives the very numbers it published; a reload with a
// broken configuration keeps the old one; SIGTERM stops it cleanly.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "daemon/config/daemon_config_yaml.hpp"
#include "daemon/pipeline_setup.hpp"
#include "io/measurement_csv.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/socket/client.hpp"
#include "realtime/recording_replay.hpp"
#include "tests/daemon/e2e/daemon_process.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;

std::string config_text(const std::filesystem::path& dir, const std::string& shm_name,
                        const std::string& calibration) {
  const std::string root = TOFCOMP_SOURCE_ROOT;
  return "emulator:\n"
         "  enabled: true\n"
         "  scenario: " +
         root +
         "/config/scenarios/default.yaml\n"
         "  time_scale: 1.0\n"
         "case_sensor:\n"
         "  backend: simulated\n"
         "  poll_interval_ms: 200\n"
         "calibration:\n"
         "  file: " +
         calibration +
         "\n"
         "outputs:\n"
         "  socket:\n"
         "    path: " +
         (dir / "tofcompd.sock").string() +
         "\n"
         "  shm:\n"
         "    name: " +
         shm_name +
         "\n"
         "recording:\n"
         "  enabled: true\n"
         "  directory: " +
         (dir / "recordings").string() +
         "\n"
         "log:\n"
         "  level: info\n"
         "  target: stderr\n";
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

const nlohmann::json& scan_of(const nlohmann::json& message) {
  return message.contains("scan") ? message["scan"] : message;
}

double number(const nlohmann::json& v) {
  return v.is_null() ? std::nan("") : v.get<double>();
}

bool same(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

TEST(DaemonEndToEnd, PublishesWhatTheReplayOfItsRecordingComputes) {
  TemporaryDirectory dir;
  const std::string shm = "/tofcomp-e2e-" + std::to_string(::getpid());
  const auto config = dir.path() / "tofcompd.yaml";
  const std::string calibration = std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml";
  write_file(config, config_text(dir.path(), shm, calibration));
  DaemonProcess daemon(config, dir.path() / "tofcompd.log");
  ASSERT_TRUE(wait_for_path(dir.path() / "tofcompd.sock", 30s)) << daemon.log();

  ipc::socket::SocketClient subscriber((dir.path() / "tofcompd.sock").string(), 5s);
  const nlohmann::json ack = subscriber.request({{"op", "subscribe"}, {"id", 1}}, 10s);
  ASSERT_TRUE(ack.value("ok", false)) << ack.dump();
  std::map<std::uint64_t, nlohmann::json> received;
  while (received.size() < 150) {
    const auto message = subscriber.read_message(30s);
    ASSERT_TRUE(message.has_value()) << "no scan within 30 s\n" << daemon.log();
    const nlohmann::json& scan = scan_of(*message);
    received[scan.at("sequence").get<std::uint64_t>()] = scan;
  }
  // In order, without gaps.
  std::uint64_t expected = received.begin()->first;
  for (const auto& [sequence, scan] : received) EXPECT_EQ(sequence, expected++);

  // The ring holds the same scans: its latest is one the socket also sent, or a newer one.
  ipc::ring::RingReader ring(shm);
  const auto latest = ring.latest();
  ASSERT_TRUE(latest.has_value());
  EXPECT_GE(latest->sequence, received.begin()->first);
  EXPECT_EQ(latest->beams.size(), 361u);

  // A client's status request while streaming.
  ipc::socket::SocketClient client((dir.path() / "tofcompd.sock").string(), 5s);
  const nlohmann::json status = client.request({{"op", "status"}}, 10s);
  ASSERT_TRUE(status.value("ok", false)) << status.dump();
  EXPECT_EQ(status["status"]["calibration"]["id"], 1);

  // A reload with a broken configuration is refused; the daemon runs on with the old one.
  write_file(config, config_text(dir.path(), shm, calibration) + "unknown_section: 1\n");
  const nlohmann::json refused = client.request({{"op", "reload"}}, 10s);
  EXPECT_FALSE(refused.value("ok", true)) << refused.dump();
  EXPECT_NE(refused.dump().find("unknown_section"), std::string::npos) << refused.dump();
  // SIGHUP reads it too, and refuses it the same way.
  daemon.signal(SIGHUP);
  const auto more = subscriber.read_message(30s);
  ASSERT_TRUE(more.has_value()) << "streaming stopped after the refused reload\n" << daemon.log();
  const nlohmann::json after = client.request({{"op", "status"}}, 10s);
  EXPECT_NE(after["status"]["last_reload"].get<std::string>().find("refused"), std::string::npos);
  EXPECT_EQ(after["status"]["calibration"]["id"], 1);

  ASSERT_EQ(daemon.terminate(), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("unknown_section"), std::string::npos);

  // The recording, replayed offline with the daemon's configuration, gives the same numbers.
  write_file(config, config_text(dir.path(), shm, calibration));
  const auto settings = daemon::config::load_daemon_config(config);
  realtime::CompensationPipeline pipeline(daemon::pipeline_settings(settings));
  pipeline.set_calibration(daemon::read_configured_calibration(settings), 1);
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir.path() / "recordings")) {
    files.push_back(e.path());
  }
  ASSERT_EQ(files.size(), 1u);
  const io::MeasurementTable table = io::read_measurements_file(files[0].string());
  std::size_t compared = 0;
  std::size_t compensated_values = 0;
  realtime::replay_recording(
      table, files[0].string(), pipeline, [&](const ipc::CompensatedScan& s) {
        const auto it = received.find(s.sequence);
        if (it == received.end()) return;
        const nlohmann::json& live = it->second;
        ASSERT_EQ(live["beams"].size(), s.beams.size());
        for (std::size_t b = 0; b < s.beams.size(); ++b) {
          const auto& l = live["beams"][b];
          const auto& r = s.beams[b];
          EXPECT_EQ(l["flags"].get<int>(), r.flags) << s.sequence;
          EXPECT_TRUE(same(number(l["raw_mm"]), r.raw_mm));
          EXPECT_TRUE(same(number(l["compensated_mm"]), r.compensated_mm))
              << s.sequence << " beam " << b;
          EXPECT_TRUE(same(number(l["window_mm"]), r.window_mm)) << s.sequence << " beam " << b;
          compensated_values += std::isfinite(r.compensated_mm);
        }
        ++compared;
      });
  EXPECT_EQ(compared, received.size());
  // Scans before the first case reading are published raw (flagged temperature_stale); after
  // it every beam with an echo is compensated.
  EXPECT_GT(compensated_values, (compared - 30) * 300);
}

}  // namespace
}  // namespace tofcomp::test
