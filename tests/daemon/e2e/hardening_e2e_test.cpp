// tofcompd against clients, local users and files that try to crash, stall or poison it
// (issue 15), end to end on the real binary: recordings a client names are refused unless they
// are regular files in the recordings directory (a FIFO, /dev/zero, a device node, a link out, a
// path outside, a file over the size limit), and control is refused to other users; a recording
// with an impossible reference distance fails training with its line; a calibration trained on a
// reference off by 500 mm is not swapped in, and status says why; a training past its time or
// memory limit is stopped and the daemon runs on; SIGTERM ends the daemon within its bound during
// a long training; a ring planted by another user does not keep it from starting, nor a dead
// daemon's pid the next start; reloads that change nothing restart no window; stale temporaries go
// at start; --check-config loads every file it names; the built-in link recovers from every fault
// the emulator injects, each kind counted. After each, the daemon still answers and stops on
// SIGTERM.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/calibration_file.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "ipc/socket/client.hpp"
#include "tests/daemon/e2e/daemon_process.hpp"
#include "tests/daemon/e2e/e2e_config.hpp"
#include "tests/support/file_text.hpp"
#include "tests/support/planted_ring.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

constexpr uid_t kNobody = 65534;  // Debian's nobody: neither root nor the test's user
// The bound docs/daemon.md states for SIGTERM to end the daemon, training or not.
constexpr auto kStopBound = 5s;

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

// The twin's default scenario as measured data in `file`, its ranges every `range_period_s`
// (the default 1.08 s gives 20,000 ranges and trains in seconds; 0.054 s gives 400,000 ranges,
// which train for minutes).
void simulate(const std::filesystem::path& dir, const std::filesystem::path& file,
              const std::string& range_period_s = "1.08") {
  std::string scenario =
      testing::file_text(std::string(TOFCOMP_SOURCE_ROOT) + "/config/scenarios/default.yaml");
  replace_all(scenario, "range_period_s: 1.08", "range_period_s: " + range_period_s);
  write_file(dir / "scenario.yaml", scenario);
  const std::string command = std::string(TOFCOMP_BINARY) + " -q simulate " +
                              (dir / "scenario.yaml").string() + " -o " + file.string();
  ASSERT_EQ(std::system(command.c_str()), 0);
}

// A daemon on the emulated LMS 200 with the bundled calibration, recalibrating from recordings
// in dir/recordings-in (bench.csv by default), with `limits` under recalibration.
struct HardenedDaemon {
  TemporaryDirectory dir;
  std::string shm;
  std::filesystem::path config;
  std::filesystem::path recordings;
  std::unique_ptr<DaemonProcess> process;

  explicit HardenedDaemon(const std::string& tag, const std::string& limits = "",
                          const std::string& extra = "") {
    const std::string root = TOFCOMP_SOURCE_ROOT;
    shm = "/tofcomp-e2e-" + tag + "-" + std::to_string(::getpid());
    recordings = dir.path() / "recordings-in";
    std::filesystem::create_directory(recordings);
    std::filesystem::copy_file(root + "/config/calibration.yaml", dir.path() / "calibration.yaml");
    config = dir.path() / "tofcompd.yaml";
    write_file(config, config_text(dir.path(), shm, "calibration.yaml") + extra +
                           "recalibration:\n"
                           "  source: recording\n"
                           "  recording: {data: recordings-in/bench.csv}\n"
                           "  datasheet: " +
                           root + "/config/lms200-datasheet.yaml\n" + limits);
  }
  void start() {
    process = std::make_unique<DaemonProcess>(config, dir.path() / "tofcompd.log");
    ASSERT_TRUE(wait_for_socket(socket(), 30s)) << process->log();
  }
  std::filesystem::path socket() const { return dir.path() / "tofcompd.sock"; }
  std::string log() const { return process ? process->log() : ""; }
  json request(const json& r) {
    ipc::socket::SocketClient client(socket().string(), 10s);
    return client.request(r, 10s);
  }
  json status() { return request({{"op", "status"}})["status"]; }
  // Polls status until `done` holds; fails the test after `limit`.
  json wait_for_status(const std::function<bool(const json&)>& done,
                       std::chrono::seconds limit = 120s) {
    const auto until = Clock::now() + limit;
    json s;
    while (Clock::now() < until) {
      s = status();
      if (done(s)) return s;
      std::this_thread::sleep_for(100ms);
    }
    ADD_FAILURE() << "status never came: " << s.dump() << "\n" << log();
    return s;
  }
  // The daemon still publishes, and then stops on SIGTERM within the bound.
  void still_serves_and_stops() {
    const auto before =
        wait_for_status([](const json& s) { return s.contains("latest"); })["latest"]["sequence"]
            .get<std::uint64_t>();
    const json later = wait_for_status(
        [&](const json& s) { return s["latest"]["sequence"].get<std::uint64_t>() > before; });
    EXPECT_GT(later["latest"]["sequence"].get<std::uint64_t>(), before);
    const auto asked = Clock::now();
    EXPECT_EQ(process->terminate(kStopBound), 0) << "not stopped within the bound\n" << log();
    std::printf("stopped %.3f s after SIGTERM\n",
                std::chrono::duration<double>(Clock::now() - asked).count());
  }
};

json recalibrate(HardenedDaemon& d, const std::string& recording) {
  return d.request({{"op", "recalibrate"}, {"args", {{"recording", recording}}}});
}

void expect_refused(const json& reply, const std::string& part) {
  EXPECT_EQ(reply.value("ok", true), false) << reply.dump();
  EXPECT_EQ(reply["error"]["code"], "refused") << reply.dump();
  EXPECT_NE(reply["error"]["message"].get<std::string>().find(part), std::string::npos)
      << reply.dump();
}

TEST(DaemonHardening, RecordingsAClientNamesAreCheckedBeforeTheyAreRead) {
  HardenedDaemon d("named", "  limits: {recording_mib: 1}\n");
  const std::filesystem::path in = d.recordings;
  ASSERT_EQ(::mkfifo((in / "fifo.csv").c_str(), 0644), 0);
  std::filesystem::create_symlink("/etc/passwd", in / "link.csv");
  write_file(d.dir.path() / "outside.csv", "time_s,range_mm,true_range_mm\n0,3000,3000\n");
  write_file(in / "huge.csv", std::string(2u << 20, '#'));
  const bool root = ::geteuid() == 0;
  if (root) {
    ASSERT_EQ(::mknod((in / "zero.csv").c_str(), S_IFCHR | 0644, ::makedev(1, 5)), 0);
  }
  d.start();

  expect_refused(recalibrate(d, "fifo.csv"), "fifo.csv: a FIFO (named pipe), not a regular file");
  expect_refused(recalibrate(d, "/dev/zero"), "/dev/zero: not a file directly in " + in.string() +
                                                  " (recalibration.recording.directory)");
  expect_refused(recalibrate(d, "link.csv"), "link.csv: a symbolic link");
  expect_refused(recalibrate(d, "../outside.csv"), "not a file directly in");
  expect_refused(recalibrate(d, (d.dir.path() / "outside.csv").string()), "not a file directly in");
  expect_refused(recalibrate(d, "huge.csv"),
                 "huge.csv: 2097152 bytes, more than the 1048576 of "
                 "recalibration.limits.recording_mib");
  if (root) expect_refused(recalibrate(d, "zero.csv"), "zero.csv: a character device");
  // Nothing was trained; the daemon answers, publishes and stops.
  EXPECT_EQ(d.status()["recalibration"], "idle");
  EXPECT_EQ(d.status()["calibration"]["id"], 1);
  d.still_serves_and_stops();
}

TEST(DaemonHardening, ControlIsRefusedToAnotherUser) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to run a client as another user";
  HardenedDaemon d("peer", "", "");
  std::string text = testing::file_text(d.config);
  replace_all(text, "  socket:\n", "  socket:\n    mode: \"0666\"\n");
  write_file(d.config, text);
  ASSERT_EQ(::chmod(d.dir.path().c_str(), 0755), 0);
  simulate(d.dir.path(), d.recordings / "bench.csv");
  d.start();
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    std::string out;
    if (::setgid(kNobody) == 0 && ::setuid(kNobody) == 0) {
      try {
        ipc::socket::SocketClient client(d.socket().string(), 10s);
        out += client.request({{"op", "recalibrate"}}, 10s).dump() + "\n";
        out += client.request({{"op", "reload"}}, 10s).dump() + "\n";
        out += client.request({{"op", "status"}}, 10s).dump() + "\n";
      } catch (const std::exception& e) {
        out += std::string("error: ") + e.what() + "\n";
      }
    }
    const ssize_t n = ::write(pipe_fds[1], out.data(), out.size());
    ::_exit(n == static_cast<ssize_t>(out.size()) ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string text_out;
  char buffer[4096];
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) {
    text_out.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(pipe_fds[0]);
  ::waitpid(child, nullptr, 0);
  std::istringstream lines(text_out);
  std::string recal, reload, status;
  std::getline(lines, recal);
  std::getline(lines, reload);
  std::getline(lines, status);
  ASSERT_FALSE(status.empty()) << text_out;
  EXPECT_EQ(json::parse(recal)["error"]["code"], "forbidden") << recal;
  EXPECT_NE(recal.find("not allowed for uid 65534"), std::string::npos) << recal;
  EXPECT_EQ(json::parse(reload)["error"]["code"], "forbidden") << reload;
  EXPECT_EQ(json::parse(status)["ok"], true) << status;
  EXPECT_EQ(d.status()["recalibration"], "idle");
  d.still_serves_and_stops();
}

TEST(DaemonHardening, AnImpossibleReferenceDistanceFailsTrainingNamingItsLine) {
  HardenedDaemon d("impossible");
  simulate(d.dir.path(), d.recordings / "bench.csv");
  // One row's reference distance is -3000 mm (the row that gives it; it holds for the rows
  // after it, as the format's reference distance does).
  std::string data = testing::file_text(d.recordings / "bench.csv");
  const std::size_t row = data.find(",3000\n");
  ASSERT_NE(row, std::string::npos);
  data.replace(row, 6, ",-3000\n");
  write_file(d.recordings / "impossible.csv", data);
  const long line =
      std::count(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(row), '\n') + 1;
  d.start();
  ASSERT_TRUE(recalibrate(d, "impossible.csv").value("ok", false));
  const json s = d.wait_for_status([](const json& st) {
    return st["recalibration"].get<std::string>().rfind("failed", 0) == 0;
  });
  const std::string state = s["recalibration"];
  EXPECT_NE(state.find("impossible.csv:" + std::to_string(line) +
                       ": column true_range_mm: -3000 mm is no distance an LMS 200 measures"),
            std::string::npos)
      << state;
  EXPECT_EQ(s["calibration"]["id"], 1);
  d.still_serves_and_stops();
}

TEST(DaemonHardening, ACalibrationTrainedOnAWrongReferenceIsNotSwappedIn) {
  HardenedDaemon d("poisoned");
  simulate(d.dir.path(), d.recordings / "bench.csv");
  std::string data = testing::file_text(d.recordings / "bench.csv");
  replace_all(data, ",3000\n", ",3500\n");  // every reference 500 mm off
  write_file(d.recordings / "poisoned.csv", data);
  const std::string before = testing::file_text(d.dir.path() / "calibration.yaml");
  d.start();
  ASSERT_TRUE(recalibrate(d, "poisoned.csv").value("ok", false));
  const json s = d.wait_for_status([](const json& st) {
    const std::string r = st["recalibration"];
    return r.rfind("rejected", 0) == 0 || r.rfind("done", 0) == 0 || r.rfind("failed", 0) == 0;
  });
  const std::string state = s["recalibration"];
  EXPECT_EQ(state.rfind("rejected: the new calibration was not swapped in (in mode ", 0), 0u)
      << state;
  EXPECT_NE(state.find("it predicts a range error of -5"), std::string::npos) << state;
  EXPECT_NE(state.find("beyond the ±50 mm an LMS 200's can be"), std::string::npos) << state;
  EXPECT_NE(state.find("calibration 1 stays"), std::string::npos) << state;
  EXPECT_EQ(s["calibration"]["id"], 1);
  // The file on disk is the one the daemon started with: nothing poisoned survives a restart.
  EXPECT_EQ(testing::file_text(d.dir.path() / "calibration.yaml"), before);
  // A good recording still recalibrates.
  ASSERT_TRUE(recalibrate(d, "bench.csv").value("ok", false));
  const json good = d.wait_for_status(
      [](const json& st) { return st["recalibration"].get<std::string>().rfind("done", 0) == 0; });
  EXPECT_EQ(good["calibration"]["id"], 2);
  EXPECT_NE(good["recalibration"].get<std::string>().find("held-out d̂ error"), std::string::npos)
      << good.dump();
  d.still_serves_and_stops();
}

TEST(DaemonHardening, SigtermEndsTheDaemonWithinItsBoundDuringALongTraining) {
  HardenedDaemon d("sigterm");
  simulate(d.dir.path(), d.recordings / "bench.csv", "0.054");  // 400,000 ranges: minutes
  d.start();
  ASSERT_TRUE(d.request({{"op", "recalibrate"}}).value("ok", false));
  const json s = d.wait_for_status([](const json& st) { return st.contains("training_pid"); });
  const pid_t trainer = s["training_pid"].get<pid_t>();
  std::this_thread::sleep_for(1s);  // well into the training, which runs for minutes
  ASSERT_EQ(::kill(trainer, 0), 0) << "the training ended before SIGTERM: not a long training";
  const auto asked = Clock::now();
  EXPECT_EQ(d.process->terminate(kStopBound), 0) << d.log();
  std::printf("stopped %.3f s after SIGTERM during a training\n",
              std::chrono::duration<double>(Clock::now() - asked).count());
  EXPECT_NE(::kill(trainer, 0), 0) << "the training process outlived the daemon";
}

TEST(DaemonHardening, ATrainingPastItsTimeLimitIsStoppedAndTheDaemonRunsOn) {
  HardenedDaemon d("time", "  limits: {time_s: 2}\n");
  simulate(d.dir.path(), d.recordings / "bench.csv", "0.054");
  d.start();
  ASSERT_TRUE(d.request({{"op", "recalibrate"}}).value("ok", false));
  const json s = d.wait_for_status([](const json& st) {
    return st["recalibration"].get<std::string>().rfind("failed", 0) == 0;
  });
  EXPECT_EQ(s["recalibration"],
            "failed: training ran longer than 2 s (recalibration.limits.time_s) and was stopped");
  EXPECT_FALSE(s.contains("training_pid"));
  EXPECT_EQ(s["calibration"]["id"], 1);
  d.still_serves_and_stops();
}

TEST(DaemonHardening, ATrainingPastItsMemoryLimitFailsAndTheDaemonRunsOn) {
  HardenedDaemon d("memory", "  limits: {memory_mib: 256}\n");
  simulate(d.dir.path(), d.recordings / "bench.csv", "0.054");  // trains in about 450 MB
  d.start();
  ASSERT_TRUE(d.request({{"op", "recalibrate"}}).value("ok", false));
  const json s = d.wait_for_status(
      [](const json& st) { return st["recalibration"].get<std::string>().rfind("failed", 0) == 0; },
      600s);
  EXPECT_NE(s["recalibration"].get<std::string>().find(
                "training needed more memory than the 268435456 bytes of "
                "recalibration.limits.memory_mib"),
            std::string::npos)
      << s.dump();
  EXPECT_EQ(s["calibration"]["id"], 1);
  d.still_serves_and_stops();
}

TEST(DaemonHardening, ARingPlantedByAnotherUserDoesNotStopTheDaemon) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to plant a ring as another user";
  HardenedDaemon d("planted");
  const std::string alternative = ipc::ring::alternative_ring_name(d.shm, ::geteuid());
  // Whatever happens below, both names are removed (after the planter is let go).
  struct Unlink {
    std::string planted;
    std::string alternative;
    ~Unlink() {
      ::shm_unlink(planted.c_str());
      ::shm_unlink(alternative.c_str());
    }
  } unlink_both{d.shm, alternative};
  // Another user takes the ring's name first and holds it, with a fake scan in it.
  const PlantedRing planted(d.shm);
  d.start();
  d.wait_for_status([](const json& s) { return s.contains("latest"); });
  const json stats = d.request({{"op", "stats"}});
  EXPECT_EQ(stats["stats"]["shm"]["name"], alternative) << stats.dump();
  EXPECT_NE(d.log().find("shm object '" + d.shm + "' belongs to uid 65534"), std::string::npos)
      << d.log();
  // A reader of the name gets the daemon's scans, not the planted one.
  ipc::ring::RingReader reader(d.shm);
  EXPECT_EQ(reader.name(), alternative);
  const auto latest = reader.latest();
  ASSERT_TRUE(latest.has_value());
  EXPECT_NE(latest->sequence, PlantedRing::kFakeSequence);
  EXPECT_EQ(latest->beams.size(), 361u);
  d.still_serves_and_stops();
}

TEST(DaemonHardening, OneDaemonPerSocketByItsLockNotItsPid) {
  HardenedDaemon d("lock");
  d.start();
  // A second daemon on the same socket (another ring name) does not start.
  std::string second = testing::file_text(d.config);
  replace_all(second, d.shm, d.shm + "-second");
  write_file(d.dir.path() / "second.yaml", second);
  DaemonProcess other(d.dir.path() / "second.yaml", d.dir.path() / "second.log");
  const auto until = Clock::now() + 30s;
  while (other.running() && Clock::now() < until) std::this_thread::sleep_for(50ms);
  EXPECT_FALSE(other.running());
  EXPECT_NE(other.log().find("another tofcompd (pid "), std::string::npos) << other.log();
  EXPECT_NE(other.log().find("runs with the socket " + d.socket().string()), std::string::npos)
      << other.log();
  // Killed with SIGKILL, the first leaves its lock file and ring behind; the next start takes
  // both over at once.
  d.process->signal(SIGKILL);
  d.process->terminate(kStopBound);
  std::filesystem::remove(d.socket());
  d.start();
  EXPECT_EQ(d.request({{"op", "stats"}})["stats"]["shm"]["name"], d.shm);
  d.still_serves_and_stops();
}

TEST(DaemonHardening, AReloadThatChangesNothingKeepsEveryWindow) {
  HardenedDaemon d("reloads");
  d.start();
  ipc::socket::SocketClient subscriber(d.socket().string(), 10s);
  ASSERT_TRUE(
      subscriber.request({{"op", "subscribe"}, {"beams", {180, 180}}}, 10s).value("ok", false));
  const auto next_scan = [&] {
    const auto message = subscriber.read_message(30s);
    if (!message) throw std::runtime_error("no scan within 30 s");
    return scan_of(*message);
  };
  // The window's estimate is published once it has its minimum of ranges.
  json scan;
  for (int i = 0; i < 200; ++i) {
    scan = next_scan();
    if (!scan["beams"][0]["window_mm"].is_null()) break;
  }
  ASSERT_FALSE(scan["beams"][0]["window_mm"].is_null()) << d.log();
  // Ten reloads of the same configuration, one every few scans: nothing restarts.
  for (int reload = 0; reload < 10; ++reload) {
    const json reply = d.request({{"op", "reload"}});
    ASSERT_TRUE(reply.value("ok", false)) << reply.dump();
    EXPECT_NE(reply["message"].get<std::string>().find("calibration 1 from"), std::string::npos)
        << reply.dump();
    for (int i = 0; i < 3; ++i) {
      scan = next_scan();
      EXPECT_FALSE(scan["beams"][0]["window_mm"].is_null())
          << "the window restarted after reload " << reload;
      EXPECT_EQ(scan["calibration_id"], 1);
    }
  }
  d.still_serves_and_stops();
}

TEST(DaemonHardening, StaleTemporariesOfInterruptedWritesGoAtStart) {
  HardenedDaemon d("stale");
  const auto stale = d.dir.path() / ".calibration.yaml.k3Jq9Z";
  const auto kept = d.dir.path() / ".calibration.yaml.notmine";
  write_file(stale, "schema: tofcomp-calibration\n");
  write_file(kept, "left alone\n");
  d.start();
  EXPECT_FALSE(std::filesystem::exists(stale));
  EXPECT_TRUE(std::filesystem::exists(kept));
  EXPECT_NE(d.log().find("removed " + stale.string()), std::string::npos) << d.log();
  d.still_serves_and_stops();
}

// The built-in default (no emulator.link: each hang-up makes a new pty) under every fault the
// emulator injects, each at one telegram in a hundred: the stats count each kind by its name, the
// kinds add up to the total, and the link recovers from all of them (issue 53, item 2).
TEST(DaemonHardening, TheBuiltInLinkRecoversFromEveryFaultTheEmulatorInjects) {
  HardenedDaemon d("faults");
  std::string text = testing::file_text(d.config);
  replace_all(text, "  time_scale: 1.0\n",
              "  time_scale: 1.0\n"
              "  faults: {garbage: 0.01, dropped_byte: 0.01, corrupted_crc: 0.01, stall: 0.01,\n"
              "           hang_up: 0.01, reset: 0.01, stall_s: 0.1}\n"
              "  fault_seed: 53\n");
  write_file(d.config, text);
  d.start();
  const std::vector<std::string> kinds = {"garbage", "dropped_byte", "corrupted_crc",
                                          "stall",   "hang_up",      "reset"};
  constexpr std::uint64_t kEachKind = 2;
  json emulator;
  const auto until = Clock::now() + 120s;
  while (Clock::now() < until) {
    emulator = d.request({{"op", "stats"}})["stats"]["emulator"];
    const json& by_kind = emulator["faults_by_kind"];
    if (std::all_of(kinds.begin(), kinds.end(), [&](const std::string& k) {
          return by_kind.contains(k) && by_kind[k].get<std::uint64_t>() >= kEachKind;
        })) {
      break;
    }
    std::this_thread::sleep_for(100ms);
  }
  ASSERT_TRUE(emulator.contains("faults_by_kind")) << emulator.dump();
  const json& by_kind = emulator["faults_by_kind"];
  EXPECT_EQ(by_kind.size(), kinds.size()) << by_kind.dump();
  std::uint64_t sum = 0;
  for (const auto& kind : kinds) {
    ASSERT_TRUE(by_kind.contains(kind)) << by_kind.dump();
    EXPECT_GE(by_kind[kind].get<std::uint64_t>(), kEachKind) << kind << ": " << emulator.dump();
    sum += by_kind[kind].get<std::uint64_t>();
  }
  EXPECT_EQ(sum, emulator["faults_injected"].get<std::uint64_t>()) << emulator.dump();
  d.still_serves_and_stops();  // scans again after the last of them
}

// tofcompd --check-config on `config`: its exit status and what it printed.
std::pair<int, std::string> check_config(const std::filesystem::path& config) {
  const std::string command =
      std::string(TOFCOMPD_BINARY) + " --check-config --config " + config.string() + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string out;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

TEST(DaemonHardening, CheckConfigLoadsEveryFileItNames) {
  HardenedDaemon d("check");
  simulate(d.dir.path(), d.recordings / "bench.csv");
  const auto [ok, valid] = check_config(d.config);
  EXPECT_EQ(ok, 0) << valid;
  EXPECT_NE(valid.find(": valid; calibration "), std::string::npos) << valid;
  EXPECT_NE(valid.find("; recording " + (d.recordings / "bench.csv").string()), std::string::npos)
      << valid;

  const auto broken = [&](const std::string& from, const std::string& to) {
    std::string text = testing::file_text(d.config);
    replace_all(text, from, to);
    write_file(d.dir.path() / "broken.yaml", text);
    return check_config(d.dir.path() / "broken.yaml");
  };
  const auto [missing_calibration, a] = broken("file: calibration.yaml", "file: gone.yaml");
  EXPECT_EQ(missing_calibration, 1) << a;
  EXPECT_NE(a.find("calibration.file " + (d.dir.path() / "gone.yaml").string()), std::string::npos)
      << a;
  const auto [missing_scenario, b] = broken("scenarios/default.yaml", "scenarios/gone.yaml");
  EXPECT_EQ(missing_scenario, 1) << b;
  EXPECT_NE(b.find("emulator.scenario"), std::string::npos) << b;
  const auto [missing_data, c] =
      broken("data: recordings-in/bench.csv", "data: recordings-in/gone.csv");
  EXPECT_EQ(missing_data, 1) << c;
  EXPECT_NE(c.find("recalibration.recording.data"), std::string::npos) << c;
  EXPECT_NE(c.find("does not exist"), std::string::npos) << c;
  const auto [missing_datasheet, e] = broken("config/lms200-datasheet.yaml", "config/gone.yaml");
  EXPECT_EQ(missing_datasheet, 1) << e;
  EXPECT_NE(e.find("recalibration.datasheet"), std::string::npos) << e;
  // A calibration the gate of a recalibration would refuse is no calibration to start with
  // either: a calibration file with a key given twice.
  std::string calibration = testing::file_text(d.dir.path() / "calibration.yaml");
  replace_all(calibration, "version: 1\n", "version: 1\nversion: 1\n");
  write_file(d.dir.path() / "twice.yaml", calibration);
  const auto [twice, f] = broken("file: calibration.yaml", "file: twice.yaml");
  EXPECT_EQ(twice, 1) << f;
  EXPECT_NE(f.find("version is given twice"), std::string::npos) << f;
  // A calibration whose file passes its own checks but which describes no scanner (a junction
  // capacity of 1e-300 J/K: 26,607 mm published for a raw 3,001 mm): refused, naming why.
  std::string no_scanner = testing::file_text(d.dir.path() / "calibration.yaml");
  const std::size_t c1 = no_scanner.find("c1_j_per_k: ");
  ASSERT_NE(c1, std::string::npos);
  no_scanner.replace(c1, no_scanner.find('\n', c1) - c1, "c1_j_per_k: 1e-300");
  write_file(d.dir.path() / "no-scanner.yaml", no_scanner);
  const auto [impossible, h] = broken("file: calibration.yaml", "file: no-scanner.yaml");
  EXPECT_EQ(impossible, 1) << h;
  EXPECT_NE(h.find("calibration.file " + (d.dir.path() / "no-scanner.yaml").string() +
                   ": not a calibration of a scanner that can exist: its thermal time constant "
                   "R1·C1 (junction over case) is"),
            std::string::npos)
      << h;
  // A ring the daemon could not reserve at start (the most slots, 60 GB): refused here too.
  const auto [too_many_slots, g] = broken("  shm:\n", "  shm:\n    slots: 1048576\n");
  EXPECT_EQ(too_many_slots, 1) << g;
  EXPECT_NE(g.find("outputs.shm.slots 1048576: "), std::string::npos) << g;
  EXPECT_NE(g.find("1048576 slots of 1024 beams need 60263760000 bytes"), std::string::npos) << g;
}

}  // namespace
}  // namespace tofcomp::test
