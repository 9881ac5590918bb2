// tofcomp-mqtt-bridge's work: tofcompd read through libtofcomp-client (a compact-frame
// subscription for the scans, a second connection for status and commands), its telemetry
// published to the broker at the configured periods, and the command topic's allowed commands
// passed to tofcompd. Either side may go away: each is reconnected with backoff (the broker by
// libmosquitto's network thread, tofcompd here), and the retained online state and the will
// stay true throughout.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "bridges/mqtt/bridge_config.hpp"
#include "bridges/mqtt/mqtt_session.hpp"
#include "bridges/mqtt/range_summary.hpp"
#include "bridges/mqtt/topics.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::bridges::mqtt {

// Commands waiting for tofcompd at once; beyond, a command is answered "unavailable" at once.
inline constexpr std::size_t kMaxQueuedCommands = 16;

class Bridge {
 public:
  Bridge(BridgeConfig config, const std::string& password);
  ~Bridge();
  // Runs until `stop` is set (by SIGTERM or SIGINT), then publishes "offline" and disconnects.
  void run(const std::atomic<bool>& stop);

 private:
  using Clock = std::chrono::steady_clock;

  void connect_tofcompd(Clock::time_point now);
  void drop_tofcompd(const std::string& why, Clock::time_point now);
  void on_scan(const client::Scan& scan, Clock::time_point now);
  void publish_status(Clock::time_point now);
  void publish_diagnosis(Clock::time_point now);
  void serve_commands();
  void queue_command(std::string payload);  // on the network thread
  void publish(const std::string& topic, std::string payload, Qos qos, bool retain);
  // Waits up to `limit` for a command or the stop flag, without a scan stream to wait on.
  void idle(std::chrono::milliseconds limit);

  BridgeConfig config_;
  Topics topics_;
  std::unique_ptr<MqttSession> session_;
  std::optional<client::Connection> stream_;   // the scans
  std::optional<client::Connection> control_;  // status, reload, recalibrate
  std::string tofcompd_error_;                 // why it is not connected, "" when it is
  std::chrono::seconds backoff_;
  Clock::time_point next_try_{};
  Clock::time_point junction_due_{};
  Clock::time_point ranges_due_{};
  Clock::time_point status_due_{};
  Clock::time_point diagnosis_due_{};
  RangeSummary summary_;
  nlohmann::json last_status_;       // null while none
  nlohmann::json last_flag_share_;   // of the last ranges period
  std::optional<std::uint32_t> published_calibration_;
  std::atomic<bool> republish_{false};  // the broker (re)connected: state topics again
  std::mutex commands_mutex_;
  std::condition_variable commands_ready_;
  std::deque<std::string> commands_;
  std::uint64_t published_ = 0;
};

}  // namespace tofcomp::bridges::mqtt
