// tofcompd end to end: the real binary on its emulated LMS 200 (a real pty) and simulated case
// sensor, read by a socket subscriber and a shared-memory reader; its recording replayed
// offline through the compensation path, and played by the emulated LMS 200 to a second
// daemon, gives the very numbers it published; a reload with a broken configuration keeps the
// old one; SIGTERM stops it cleanly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>

#include "core/effect_grammar.hpp"
#include "io/calibration_file.hpp"
#include "io/measured_data_csv.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/socket/client.hpp"
#include "realtime/recording_replay.hpp"
#include "settings/daemon_config_yaml.hpp"
#include "settings/pipeline_setup.hpp"
#include "tests/daemon/e2e/daemon_process.hpp"
#include "tests/daemon/e2e/e2e_config.hpp"
#include "tests/support/extensions.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;

// The daemon's compensation path as its configuration file builds it, its calibration set: the
// offline replay of what the daemon recorded.
realtime::CompensationPipeline configured_pipeline(const std::filesystem::path& config) {
  const auto daemon_config = settings::load_daemon_config(config);
  realtime::CompensationPipeline pipeline(settings::pipeline_settings(daemon_config));
  pipeline.set_calibration(settings::read_configured_calibration(daemon_config), 1);
  return pipeline;
}

// The recordings the daemon wrote under dir/recordings.
std::vector<std::filesystem::path> recordings_in(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir / "recordings")) {
    files.push_back(e.path());
  }
  return files;
}

TEST(DaemonEndToEnd, PublishesWhatTheReplayOfItsRecordingComputes) {
  TemporaryDirectory dir;
  const std::string shm = "/tofcomp-e2e-" + std::to_string(::getpid());
  const auto config = dir.path() / "tofcompd.yaml";
  const std::string calibration = std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml";
  write_file(config, config_text(dir.path(), shm, calibration));
  DaemonProcess daemon(config, dir.path() / "tofcompd.log");
  ASSERT_TRUE(wait_for_socket(dir.path() / "tofcompd.sock", 30s)) << daemon.log();

  ipc::socket::SocketClient subscriber((dir.path() / "tofcompd.sock").string(), 5s);
  // Beams 150 to 210 (61 of 361): the test's JSON parsing keeps up on a loaded machine.
  const nlohmann::json ack =
      subscriber.request({{"op", "subscribe"}, {"id", 1}, {"beams", {150, 210}}}, 10s);
  ASSERT_TRUE(ack.value("ok", false)) << ack.dump();
  std::map<std::uint64_t, nlohmann::json> received;
  ASSERT_NO_FATAL_FAILURE(collect_scans(
      subscriber, 150, [&] { return daemon.log(); }, received));
  // In order, without gaps.
  std::uint64_t expected = received.begin()->first;
  for (const auto& [sequence, scan] : received) EXPECT_EQ(sequence, expected++);

  // The ring holds the same scans: its latest is one the socket also sent, or a newer one.
  ipc::ring::RingReader ring(shm);
  const auto latest = ring.latest();
  ASSERT_TRUE(latest.has_value());
  EXPECT_GE(latest->sequence, received.begin()->first);
  EXPECT_EQ(latest->beams.size(), 361u);  // the ring holds every beam

  // Each scan carries when its rays were measured: a 0.5° scan interlaces two turns, and its
  // first ray precedes the arrival by the line time of its 732 bytes at 500 kBd (14.64 ms) and
  // its sweep (19.96 ms), docs/protocol.md "Time".
  for (const auto& [sequence, scan] : received) {
    ASSERT_TRUE(scan["rays"].is_object()) << scan.dump().substr(0, 300);
    const double before_ms = static_cast<double>(scan["timestamp_ns"].get<std::int64_t>() -
                                                 scan["rays"]["first_ray_ns"].get<std::int64_t>()) /
                             1e6;
    EXPECT_NEAR(before_ms, 14.64 + 19.963, 0.01) << sequence;
    EXPECT_EQ(scan["rays"]["interlaced_turns"], 2);
  }
  EXPECT_EQ(latest->rays.interlaced_turns, 2u);

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
  std::optional<nlohmann::json> more;
  try {
    more = subscriber.read_message(30s);
  } catch (const std::exception& e) {
    FAIL() << e.what() << "\n" << daemon.log();
  }
  ASSERT_TRUE(more.has_value()) << "streaming stopped after the refused reload\n" << daemon.log();
  const nlohmann::json after = client.request({{"op", "status"}}, 10s);
  EXPECT_NE(after["status"]["last_reload"].get<std::string>().find("refused"), std::string::npos);
  EXPECT_EQ(after["status"]["calibration"]["id"], 1);

  ASSERT_EQ(daemon.terminate(), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("unknown_section"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists("/dev/shm" + shm)) << "the ring outlived tofcompd";

  // The recording, replayed offline with the daemon's configuration, gives the same numbers.
  write_file(config, config_text(dir.path(), shm, calibration));
  realtime::CompensationPipeline pipeline = configured_pipeline(config);
  const std::vector<std::filesystem::path> files = recordings_in(dir.path());
  ASSERT_EQ(files.size(), 1u);
  const io::MeasurementTable table = io::read_measured_data_file(files[0].string());
  std::size_t compared = 0;
  std::size_t compensated_values = 0;
  realtime::replay_recording(
      table, files[0].string(), pipeline, [&](const ipc::CompensatedScan& s) {
        const auto it = received.find(s.sequence);
        if (it == received.end()) return;
        const nlohmann::json& live = it->second;
        ASSERT_EQ(live["beams"].size(), 61u);
        for (std::size_t i = 0; i < 61; ++i) {
          const std::size_t b = 150 + i;
          const auto& l = live["beams"][i];
          ASSERT_EQ(l["index"].get<std::size_t>(), b);
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
  EXPECT_GT(compensated_values, (compared - 30) * 55);

  // The recording played by the emulated LMS 200 to a second daemon: it receives the same
  // scans in the same order, none lost, with the recorded case readings at their recorded
  // instants relative to them, so it publishes the first daemon's very numbers: the same
  // sequence numbers, junction temperatures, compensated ranges, window estimates, modes and
  // flags (docs/daemon.md, "Recording and replay"). These are the daemons' first seconds, while
  // the junction filter settles from its prior: sampling the temperatures anew would differ.
  const std::string replay_shm = shm + "-replay";
  std::string replay_config = config_text(dir.path() / "replay", replay_shm, calibration);
  replay_config.replace(replay_config.find("  time_scale: 1.0\n"), 0,
                        "  recording: " + files[0].string() + "\n");
  replay_config.replace(replay_config.find("recording:\n  enabled: true"),
                        std::string("recording:\n  enabled: true").size(),
                        "recording:\n  enabled: false");
  std::filesystem::create_directory(dir.path() / "replay");
  write_file(dir.path() / "replay" / "tofcompd.yaml", replay_config);
  DaemonProcess replay(dir.path() / "replay" / "tofcompd.yaml", dir.path() / "replay.log");
  ASSERT_TRUE(wait_for_socket(dir.path() / "replay" / "tofcompd.sock", 30s)) << replay.log();
  ipc::socket::SocketClient replay_subscriber((dir.path() / "replay" / "tofcompd.sock").string(),
                                              5s);
  ASSERT_TRUE(replay_subscriber.request({{"op", "subscribe"}, {"beams", {150, 210}}}, 10s)
                  .value("ok", false));
  // The first daemon's scans by their raw ranges (the same scan has the same 61 ranges).
  std::map<std::vector<double>, std::uint64_t> by_raw;
  const auto raw_of = [](const nlohmann::json& scan) {
    std::vector<double> raw;
    for (const auto& b : scan["beams"]) raw.push_back(number(b["raw_mm"]));
    return raw;
  };
  for (const auto& [sequence, scan] : received) by_raw[raw_of(scan)] = sequence;
  std::optional<std::uint64_t> last_match;
  std::size_t matched = 0;
  std::size_t compared_beams = 0;
  while (matched < 100) {
    std::optional<nlohmann::json> message;
    try {
      message = replay_subscriber.read_message(30s);
    } catch (const std::exception& e) {
      FAIL() << e.what() << "\n" << replay.log();
    }
    ASSERT_TRUE(message.has_value()) << "the replaying daemon sent nothing\n" << replay.log();
    const nlohmann::json& scan = scan_of(*message);
    const auto it = by_raw.find(raw_of(scan));
    if (it == by_raw.end()) {
      // Before the first daemon's subscription began, or after its last scan.
      if (last_match) break;
      continue;
    }
    if (last_match) {
      ASSERT_EQ(it->second, *last_match + 1) << "a scan was lost or reordered";
    }
    last_match = it->second;
    ++matched;
    const nlohmann::json& original = received.at(it->second);
    // Every scan of the recording reached the second daemon: it numbers them the same.
    EXPECT_EQ(scan["sequence"], original["sequence"]);
    EXPECT_TRUE(same(number(scan["junction_c"]), number(original["junction_c"])))
        << "scan " << it->second << ": junction " << scan["junction_c"] << " replayed, "
        << original["junction_c"] << " live";
    EXPECT_TRUE(same(number(scan["junction_std_c"]), number(original["junction_std_c"])));
    for (std::size_t i = 0; i < 61; ++i) {
      const auto& a = original["beams"][i];
      const auto& b = scan["beams"][i];
      EXPECT_EQ(b["flags"], a["flags"]) << "scan " << it->second << " beam " << 150 + i;
      EXPECT_EQ(b["most_probable_mode"], a["most_probable_mode"])
          << "scan " << it->second << " beam " << 150 + i;
      EXPECT_TRUE(same(number(b["compensated_mm"]), number(a["compensated_mm"])))
          << "scan " << it->second << " beam " << 150 + i << ": " << b["compensated_mm"]
          << " replayed, " << a["compensated_mm"] << " live";
      EXPECT_TRUE(same(number(b["window_mm"]), number(a["window_mm"])))
          << "scan " << it->second << " beam " << 150 + i;
      EXPECT_TRUE(same(number(b["window_std_mm"]), number(a["window_std_mm"])))
          << "scan " << it->second << " beam " << 150 + i;
      compared_beams += !a["compensated_mm"].is_null();
    }
  }
  EXPECT_GE(matched, 100u);
  EXPECT_GT(compared_beams, 0u);
  EXPECT_EQ(replay.terminate(), 0) << replay.log();
}

// Recalibration from a recording: the daemon trains in its worker thread while it keeps
// publishing, writes the calibration atomically and swaps it in between two scans: the scans
// go on without a gap, the later ones carry the new calibration's id, and the file written is
// a complete calibration.
// In `dir`: the twin's record of `scenario` as the recording `data`, the shipped calibration as
// calibration.yaml, and a configuration (returned) that recalibrates from that recording, its
// ring named after `label`.
std::filesystem::path write_recalibration_setup(const TemporaryDirectory& dir,
                                                const std::string& scenario,
                                                const std::filesystem::path& data,
                                                const std::string& label) {
  const std::string root = TOFCOMP_SOURCE_ROOT;
  const std::string simulate = std::string(TOFCOMP_BINARY) + " -q simulate " + root +
                               "/config/scenarios/" + scenario + ".yaml -o " + data.string();
  if (std::system(simulate.c_str()) != 0) throw std::runtime_error("failed: " + simulate);
  std::filesystem::copy_file(root + "/config/calibration.yaml", dir.path() / "calibration.yaml");
  const std::string shm = "/tofcomp-e2e-" + label + "-" + std::to_string(::getpid());
  const auto config = dir.path() / "tofcompd.yaml";
  write_file(config, config_text(dir.path(), shm, "calibration.yaml") +
                         "recalibration:\n"
                         "  source: recording\n"
                         "  recording: {data: " + data.filename().string() + "}\n");
  // No recalibration.datasheet: the training starts from the LMS 200 datasheet built in.
  return config;
}

TEST(DaemonEndToEnd, RecalibratesWithoutLosingAScan) {
  TemporaryDirectory dir;
  const auto data = dir.path() / "bench.csv";
  const auto config = write_recalibration_setup(dir, "default", data, "recal");
  DaemonProcess daemon(config, dir.path() / "tofcompd.log");
  ASSERT_TRUE(wait_for_socket(dir.path() / "tofcompd.sock", 30s)) << daemon.log();
  ipc::socket::SocketClient subscriber((dir.path() / "tofcompd.sock").string(), 5s);
  ASSERT_TRUE(
      subscriber.request({{"op", "subscribe"}, {"beams", {180, 180}}}, 10s).value("ok", false));
  // A scan under the first calibration before the recalibration starts, so that the swap has
  // scans on both sides however fast the training is.
  const auto before = subscriber.read_message(30s);
  ASSERT_TRUE(before.has_value()) << daemon.log();
  ASSERT_EQ(scan_of(*before).at("calibration_id").get<int>(), 1);
  ipc::socket::SocketClient client((dir.path() / "tofcompd.sock").string(), 5s);
  const nlohmann::json started = client.request({{"op", "recalibrate"}}, 10s);
  ASSERT_TRUE(started.value("ok", false)) << started.dump();

  std::optional<std::uint64_t> previous = scan_of(*before).at("sequence").get<std::uint64_t>();
  std::uint64_t first_new = 0;
  for (const auto until = std::chrono::steady_clock::now() + 120s;
       std::chrono::steady_clock::now() < until;) {
    const auto message = subscriber.read_message(30s);
    ASSERT_TRUE(message.has_value()) << daemon.log();
    const nlohmann::json& scan = scan_of(*message);
    const auto sequence = scan.at("sequence").get<std::uint64_t>();
    if (previous) {
      ASSERT_EQ(sequence, *previous + 1) << "a scan was lost";
    }
    previous = sequence;
    if (scan.at("calibration_id").get<int>() == 2) {
      first_new = sequence;
      break;
    }
    ASSERT_EQ(scan.at("calibration_id").get<int>(), 1);
  }
  ASSERT_GT(first_new, 0u) << "the new calibration was not swapped in\n" << daemon.log();
  const nlohmann::json status = client.request({{"op", "status"}}, 10s);
  EXPECT_EQ(status["status"]["recalibration"].get<std::string>().rfind("done", 0), 0u)
      << status.dump();
  // The file written is a whole calibration, trained on the recording.
  const core::Calibration written =
      io::read_calibration_file((dir.path() / "calibration.yaml").string());
  EXPECT_EQ(written.provenance.data_set, data.string());
  EXPECT_EQ(daemon.terminate(), 0) << daemon.log();
}

// Closing the loop in the daemon: a recalibration from a recording with a time drift (the twin's
// effect-time-drift scenario) runs the model search on the part it trains on, and the calibration
// swapped in carries the drift term: status names it, the file written holds it, and the
// recalibration's note says what the search kept.
TEST(DaemonEndToEnd, RecalibrationCarriesWhatTheModelSearchKeeps) {
  TemporaryDirectory dir;
  const auto config =
      write_recalibration_setup(dir, "effect-time-drift", dir.path() / "drift.csv", "search");
  DaemonProcess daemon(config, dir.path() / "tofcompd.log");
  ASSERT_TRUE(wait_for_socket(dir.path() / "tofcompd.sock", 30s)) << daemon.log();
  ipc::socket::SocketClient client((dir.path() / "tofcompd.sock").string(), 5s);
  const nlohmann::json started = client.request({{"op", "recalibrate"}}, 10s);
  ASSERT_TRUE(started.value("ok", false)) << started.dump();
  nlohmann::json status;
  std::string state;
  for (const auto until = std::chrono::steady_clock::now() + 300s;
       std::chrono::steady_clock::now() < until;) {
    status = client.request({{"op", "status"}}, 10s);
    state = status["status"]["recalibration"].get<std::string>();
    if (state.rfind("done", 0) == 0 || state.rfind("failed", 0) == 0 ||
        state.rfind("rejected", 0) == 0) {
      break;
    }
    std::this_thread::sleep_for(200ms);
  }
  ASSERT_EQ(state.rfind("done", 0), 0u) << status.dump() << "\n" << daemon.log();
  const std::string drift = core::effect_name({core::Parameter::Bias, core::Covariate::Time});
  EXPECT_NE(state.find("the model search kept " + drift), std::string::npos) << state;
  const nlohmann::json& calibration = status["status"]["calibration"];
  EXPECT_EQ(calibration["id"], 2) << status.dump();
  ASSERT_TRUE(calibration["extension"].is_string()) << status.dump();
  EXPECT_EQ(calibration["extension"].get<std::string>().rfind(drift, 0), 0u) << status.dump();
  const core::Calibration written =
      io::read_calibration_file((dir.path() / "calibration.yaml").string());
  ASSERT_TRUE(written.extension.has_value());
  EXPECT_EQ(written.extension->name(), calibration["extension"].get<std::string>());
  EXPECT_EQ(daemon.terminate(), 0) << daemon.log();
}

// A calibration with a model extension (here the outlier component, written by hand onto the
// shipped calibration), loaded from the configuration: the daemon's status and stats name the
// extension, the emulated LMS 200 playing the outlier scenario gets its outliers flagged, its
// recording replayed offline gives the very numbers it published, and a reload to the plain
// calibration says so (extension null).
TEST(DaemonEndToEnd, CompensatesWithACalibrationsExtension) {
  TemporaryDirectory dir;
  const std::string root = TOFCOMP_SOURCE_ROOT;
  core::Calibration extended = io::read_calibration_file(root + "/config/calibration.yaml");
  core::ModelExtension extension =
      tofcomp::testing::structure_extension(extended.model.mixture, core::Parameter::Outliers);
  extension.extended_mixture.outlier_weight = 0.02;
  extension.extended_mixture.outlier_density = 1.0 / 200.0;
  extended.extension = extension;
  io::write_calibration_file((dir.path() / "extended.yaml").string(), extended);
  const std::string shm = "/tofcomp-e2e-ext-" + std::to_string(::getpid());
  const auto config = dir.path() / "tofcompd.yaml";
  write_file(config, config_text(dir.path(), shm, "extended.yaml", "effect-outliers"));
  DaemonProcess daemon(config, dir.path() / "tofcompd.log");
  ASSERT_TRUE(wait_for_socket(dir.path() / "tofcompd.sock", 30s)) << daemon.log();

  ipc::socket::SocketClient subscriber((dir.path() / "tofcompd.sock").string(), 5s);
  ASSERT_TRUE(
      subscriber.request({{"op", "subscribe"}, {"beams", {150, 210}}}, 10s).value("ok", false));
  std::map<std::uint64_t, nlohmann::json> received;
  ASSERT_NO_FATAL_FAILURE(collect_scans(
      subscriber, 300, [&] { return daemon.log(); }, received));
  std::size_t outliers = 0;
  std::size_t compensated = 0;
  for (const auto& [sequence, scan] : received) {
    for (const auto& b : scan["beams"]) {
      outliers += (b["flags"].get<int>() & ipc::kBeamOutlier) != 0;
      compensated += !b["compensated_mm"].is_null();
    }
  }
  ipc::socket::SocketClient client((dir.path() / "tofcompd.sock").string(), 5s);
  const nlohmann::json status = client.request({{"op", "status"}}, 10s);
  ASSERT_TRUE(status.value("ok", false)) << status.dump();
  EXPECT_EQ(status["status"]["calibration"]["extension"], "outliers") << status.dump();
  const nlohmann::json stats = client.request({{"op", "stats"}}, 10s);
  EXPECT_EQ(stats["stats"]["calibration"]["extension"], "outliers") << stats.dump();
  // The scenario's 2 % outliers within ±100 mm: flagged, and not many more.
  std::printf("%zu of %zu compensated ranges flagged outliers\n", outliers, compensated);
  EXPECT_GT(compensated, 200u * 55u);
  EXPECT_GT(outliers, 0u);
  EXPECT_LT(outliers, compensated / 20);

  // A reload to the plain calibration: the status says there is no extension.
  write_file(config,
             config_text(dir.path(), shm, root + "/config/calibration.yaml", "effect-outliers"));
  const nlohmann::json reloaded = client.request({{"op", "reload"}}, 10s);
  ASSERT_TRUE(reloaded.value("ok", false)) << reloaded.dump();
  const nlohmann::json plain = client.request({{"op", "status"}}, 10s);
  EXPECT_EQ(plain["status"]["calibration"]["id"], 2);
  EXPECT_TRUE(plain["status"]["calibration"]["extension"].is_null()) << plain.dump();
  ASSERT_EQ(daemon.terminate(), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("with the outliers extension"), std::string::npos) << daemon.log();

  // The recording replayed offline with the extended calibration: the same numbers, bit for
  // bit, up to the reload.
  write_file(config, config_text(dir.path(), shm, "extended.yaml", "effect-outliers"));
  realtime::CompensationPipeline pipeline = configured_pipeline(config);
  const std::vector<std::filesystem::path> files = recordings_in(dir.path());
  ASSERT_EQ(files.size(), 1u);
  const io::MeasurementTable table = io::read_measured_data_file(files[0].string());
  std::size_t compared = 0;
  realtime::replay_recording(
      table, files[0].string(), pipeline, [&](const ipc::CompensatedScan& s) {
        const auto it = received.find(s.sequence);
        if (it == received.end()) return;
        for (std::size_t i = 0; i < 61; ++i) {
          const auto& l = it->second["beams"][i];
          const auto& r = s.beams[150 + i];
          EXPECT_EQ(l["flags"].get<int>(), r.flags) << s.sequence;
          EXPECT_TRUE(same(number(l["compensated_mm"]), r.compensated_mm)) << s.sequence;
          EXPECT_TRUE(same(number(l["window_mm"]), r.window_mm)) << s.sequence;
        }
        ++compared;
      });
  EXPECT_EQ(compared, received.size());
}

}  // namespace
}  // namespace tofcomp::test
