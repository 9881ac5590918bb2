#include "bridges/ros2/bridge_loop.hpp"

#include <algorithm>
#include <ctime>
#include <optional>
#include <thread>

#include "bridges/ros2/dds_publisher.hpp"
#include "bridges/ros2/laser_scan.hpp"
#include "bridges/ros2/scanner_diagnostics.hpp"
#include "core/error.hpp"

namespace tofcomp::bridges::ros2 {

namespace {

using Clock = std::chrono::steady_clock;

std::int64_t realtime_ns() {
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
}

// One connection's life: subscribe, publish each scan, report every period, until `stop` or a
// client::Error (the daemon gone, a reply that did not come).
class Session {
 public:
  Session(const BridgeConfig& config, DdsPublisher& dds)
      : config_(config),
        dds_(dds),
        scans_(config.socket_path, kRequestTimeout),
        status_(config.socket_path, kRequestTimeout),
        period_(std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(config.diagnostics_period_s))) {
    scans_.subscribe(std::nullopt, 1, client::Format::Compact, kRequestTimeout);
  }

  void run(const std::atomic<bool>& stop, std::ostream& log) {
    Clock::time_point report_due = Clock::now() + period_;
    while (!stop.load()) {
      const auto wait = std::min<Clock::duration>(kPollInterval, report_due - Clock::now());
      const auto timeout = std::chrono::duration_cast<std::chrono::milliseconds>(wait);
      if (std::optional<client::Scan> scan = scans_.next_scan(std::max(timeout, {}))) publish(*scan, log);
      if (Clock::now() >= report_due) {
        report();
        report_due += period_;
        if (report_due < Clock::now()) report_due = Clock::now() + period_;  // fell behind
      }
    }
  }

 private:
  void publish(const client::Scan& scan, std::ostream& log) {
    try {
      dds_.publish_scan(laser_scan_from(scan), config_.frame_id);
    } catch (const core::Error& e) {
      log << "tofcomp-ros2-bridge: scan " << scan.info.sequence << " not published: " << e.what()
          << std::endl;
    }
    beams_.add(scan);
    latest_ = scan.info;
  }

  void report() {
    const nlohmann::json reply = nlohmann::json::parse(status_.call(R"({"op":"status"})"));
    dds_.publish_diagnostics(realtime_ns(), scanner_diagnostics(reply.at("status"), latest_,
                                                                beams_, config_.socket_path));
    beams_.clear();
  }

  const BridgeConfig& config_;
  DdsPublisher& dds_;
  client::Connection scans_;
  client::Connection status_;
  Clock::duration period_;
  FlaggedBeams beams_;
  std::optional<client::ScanInfo> latest_;
};

// Sleeps for `duration` in steps of kPollInterval; false when `stop` was set.
bool wait_unless_stopped(std::chrono::milliseconds duration, const std::atomic<bool>& stop) {
  const auto until = Clock::now() + duration;
  while (!stop.load() && Clock::now() < until) std::this_thread::sleep_for(kPollInterval);
  return !stop.load();
}

}  // namespace

void run_bridge(const BridgeConfig& config, const std::atomic<bool>& stop, std::ostream& log) {
  DdsPublisher dds(config.domain_id, config.scan_topic, config.diagnostics_topic);
  log << "tofcomp-ros2-bridge: " << describe_bridge(config) << std::endl;
  std::string last_error;
  while (!stop.load()) {
    try {
      Session session(config, dds);
      if (!last_error.empty()) log << "tofcomp-ros2-bridge: connected again" << std::endl;
      last_error.clear();
      session.run(stop, log);
    } catch (const std::exception& e) {  // client::Error, or a status reply that does not parse
      if (e.what() != last_error) log << "tofcomp-ros2-bridge: " << e.what() << std::endl;
      last_error = e.what();
      dds.publish_diagnostics(realtime_ns(), unreachable_diagnostics(config.socket_path, e.what()));
      if (!wait_unless_stopped(kReconnectInterval, stop)) break;
    }
  }
}

}  // namespace tofcomp::bridges::ros2
