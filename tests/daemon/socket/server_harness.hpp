// A SocketServer on a real Unix socket in a temporary directory, its io_context run by a thread
// of its own, with a fake daemon behind it; and the scans the tests publish.
#pragma once

#include <boost/asio.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "daemon/socket/request_handler.hpp"
#include "daemon/socket/socket_server.hpp"
#include "ipc/socket/client.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::test {

namespace sock = tofcomp::daemon::socket;

// How long a test waits for an answer or an event before it fails.
inline constexpr auto kTimeout = std::chrono::seconds(30);

// The fake daemon: answers from fields the test sets (before the server runs, or on its
// thread through SocketHarness::on_io).
class FakeDaemon : public sock::SocketRequestHandler {
 public:
  std::optional<ipc::CompensatedScan> latest;
  nlohmann::json status_doc{{"link", "streaming"}, {"scans", 12}};
  nlohmann::json stats_doc{{"scans", 12}, {"crc_errors", 0}};
  sock::ReloadResult reload_result{true, "reloaded calibration 3"};
  sock::RecalibrationResult recalibration_result{true, "recalibration started"};
  bool status_throws = false;
  std::string recalibrate_invalid;  // when set, recalibrate throws core::InvalidInput with it
  int reloads = 0;
  std::vector<nlohmann::json> recalibrate_args;

  const ipc::CompensatedScan* latest_scan() override { return latest ? &*latest : nullptr; }
  nlohmann::json status() override {
    if (status_throws) throw std::runtime_error("the status table is gone");
    return status_doc;
  }
  nlohmann::json stats() override { return stats_doc; }
  sock::ReloadResult reload() override {
    ++reloads;
    return reload_result;
  }
  sock::RecalibrationResult recalibrate(const nlohmann::json& args) override {
    if (!recalibrate_invalid.empty()) throw core::InvalidInput(recalibrate_invalid);
    recalibrate_args.push_back(args);
    return recalibration_result;
  }
};

// A scan whose every value is a known function of its sequence and beam index.
// The next line a client reads, as JSON; throws when none comes within `timeout`.
inline nlohmann::json read_json_line(ipc::socket::SocketClient& client,
                                     std::chrono::milliseconds timeout) {
  const auto line = client.read_line(timeout);
  if (!line) throw std::runtime_error("no line within the timeout");
  return nlohmann::json::parse(*line);
}

// `count` request lines {"id":i,"op":op} for i = 0, 1, ..., each ended by '\n'.
inline std::string numbered_requests(const std::string& op, int count) {
  std::string requests;
  for (int i = 0; i < count; ++i) {
    requests += R"({"id":)" + std::to_string(i) + R"(,"op":")" + op + "\"}\n";
  }
  return requests;
}

inline double raw_of(std::uint64_t sequence, std::size_t beam) {
  return 1000.0 + static_cast<double>(sequence % 1000) + static_cast<double>(beam);
}
inline ipc::CompensatedScan make_scan(std::uint64_t sequence, std::size_t beams = 361) {
  ipc::CompensatedScan s;
  s.sequence = sequence;
  s.device_sequence = sequence + 5;
  s.timestamp_ns = 1700000000000000000 + static_cast<std::int64_t>(sequence) * 13333333;
  s.junction_c = 40.0 + 0.01 * static_cast<double>(sequence);
  s.junction_std_c = 0.2;
  s.case_c = 35.0;
  s.start_angle_deg = 0.0;
  s.resolution_deg = 0.5;
  s.calibration_id = 1;
  s.beams.resize(beams);
  for (std::size_t i = 0; i < beams; ++i) {
    ipc::BeamValue& b = s.beams[i];
    b.raw_mm = raw_of(sequence, i);
    b.compensated_mm = b.raw_mm - 12.5;
    b.window_mm = i % 10 == 0 ? std::nan("") : b.raw_mm - 12.25;
    b.window_std_mm = 0.5;
    b.mode_count = 2;
    b.mode_posterior = {0.75f, 0.25f, 0.0f, 0.0f};
    b.flags = i % 10 == 0 ? ipc::kBeamWindowRestarting : 0;
  }
  return s;
}

class SocketHarness {
 public:
  explicit SocketHarness(sock::SocketServerSettings settings = {})
      : settings_(std::move(settings)), work_(boost::asio::make_work_guard(io_)) {
    settings_.path = (dir_ / "tofcompd.sock").string();
    io_thread_ = std::thread([this] { io_.run(); });
  }
  ~SocketHarness() {
    on_io([this] { servers_.clear(); });
    work_.reset();
    io_.stop();
    io_thread_.join();
  }
  SocketHarness(const SocketHarness&) = delete;
  SocketHarness& operator=(const SocketHarness&) = delete;

  // Runs f on the io thread and returns what it returned (or throws what it threw).
  template <typename F>
  auto on_io(F f) -> decltype(f()) {
    auto task = std::make_shared<std::packaged_task<decltype(f())()>>(std::move(f));
    auto result = task->get_future();
    boost::asio::post(io_, [task] { (*task)(); });
    if (result.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
      throw std::runtime_error("the io thread did not run a task within 60 s");
    }
    return result.get();
  }

  // Makes and starts a server on the harness's path (another one when called again).
  sock::SocketServer& start_server() {
    return on_io([this]() -> sock::SocketServer& {
      auto server = std::make_unique<sock::SocketServer>(
          io_, settings_, daemon_, [this](sock::SocketLogLevel, const std::string& message) {
            std::lock_guard lock(log_mutex_);
            log_.push_back(message);
          });
      server->start();
      servers_.push_back(std::move(server));
      return *servers_.back();
    });
  }
  // start_server() for a start that is to fail: the error's message, caught on the io thread
  // (an exception is not carried across threads); nullopt when the server started.
  std::optional<std::string> start_server_error() {
    return on_io([this]() -> std::optional<std::string> {
      try {
        sock::SocketServer server(io_, settings_, daemon_);
        server.start();
        return std::nullopt;
      } catch (const core::Error& e) {
        return std::string(e.what());
      }
    });
  }
  sock::SocketServer& server() { return *servers_.front(); }

  sock::SocketServerCounters counters() {
    return on_io([this] { return server().counters(); });
  }
  void publish(const ipc::CompensatedScan& scan) {
    on_io([&] { server().publish(scan); });
  }
  // Polls (on the io thread) until predicate(counters) holds; false after timeout.
  template <typename Predicate>
  bool wait_for_counters(Predicate predicate,
                         std::chrono::milliseconds timeout = std::chrono::seconds(30)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (predicate(counters())) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  std::vector<std::string> log() const {
    std::lock_guard lock(log_mutex_);
    return log_;
  }

  boost::asio::io_context& io() { return io_; }
  FakeDaemon& daemon() { return daemon_; }
  const std::string& path() const { return settings_.path; }
  void set_path(const std::string& path) { settings_.path = path; }  // before start_server
  std::string dir() const { return dir_.path().string(); }
  const sock::SocketServerSettings& settings() const { return settings_; }

 private:
  test::TemporaryDirectory dir_{"tofcomp-sock", test::kSocketParent};
  sock::SocketServerSettings settings_;
  FakeDaemon daemon_;
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  std::vector<std::unique_ptr<sock::SocketServer>> servers_;
  mutable std::mutex log_mutex_;
  std::vector<std::string> log_;
  std::thread io_thread_;
};

}  // namespace tofcomp::test
