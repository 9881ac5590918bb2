// What the end-to-end tests share: the daemon's configuration for a run on its emulated LMS 200
// in a temporary directory, and reading the scans its socket sends.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "ipc/socket/client.hpp"

namespace tofcomp::test {

// The daemon on the emulated LMS 200 of `scenario` (config/scenarios/) at time scale 1, its
// simulated case sensor read every 200 ms, `calibration`, recording into dir/recordings, its socket
// in `dir` and its ring at `shm_name`.
inline std::string config_text(const std::filesystem::path& dir, const std::string& shm_name,
                               const std::string& calibration,
                               const std::string& scenario = "default") {
  const std::string root = TOFCOMP_SOURCE_ROOT;
  return "emulator:\n"
         "  enabled: true\n"
         "  scenario: " +
         root + "/config/scenarios/" + scenario +
         ".yaml\n"
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
         "    max_queued_bytes_per_client: 16777216\n"
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

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

inline const nlohmann::json& scan_of(const nlohmann::json& message) {
  return message.contains("scan") ? message["scan"] : message;
}

inline double number(const nlohmann::json& v) {
  return v.is_null() ? std::nan("") : v.get<double>();
}

inline bool same(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

// Reads a subscription's scans until `count` sequence numbers have arrived, keyed by sequence.
// A read error or 30 s without a scan fails the test with log() (the daemon's log at that
// moment). Call it inside ASSERT_NO_FATAL_FAILURE.
inline void collect_scans(ipc::socket::SocketClient& subscriber, std::size_t count,
                          const std::function<std::string()>& log,
                          std::map<std::uint64_t, nlohmann::json>& received) {
  while (received.size() < count) {
    std::optional<nlohmann::json> message;
    try {
      message = subscriber.read_message(std::chrono::seconds(30));
    } catch (const std::exception& e) {
      FAIL() << e.what() << "\n" << log();
    }
    ASSERT_TRUE(message.has_value()) << "no scan within 30 s\n" << log();
    const nlohmann::json& scan = scan_of(*message);
    received[scan.at("sequence").get<std::uint64_t>()] = scan;
  }
}

}  // namespace tofcomp::test
