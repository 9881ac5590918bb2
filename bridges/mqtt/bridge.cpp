// The bridge's loop: one thread reads tofcompd and publishes; libmosquitto's thread carries the
// broker's side and queues the command topic's messages here.
#include "bridges/mqtt/bridge.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>

#include "bridges/mqtt/remote_command.hpp"
#include "bridges/mqtt/telemetry.hpp"
#include "ipc/socket/protocol_error.hpp"
#include "ipc/socket/reply.hpp"

namespace tofcomp::bridges::mqtt {

namespace {

using namespace std::chrono_literals;

// The longest the loop waits for anything: commands and the stop flag are seen within this.
constexpr auto kLoopSlice = 100ms;
// Connecting and exchanging hello with tofcompd, and its answer to status.
constexpr auto kTofcompdTimeout = 2000ms;
// A reload reads a calibration and a recalibrate checks a recording before tofcompd answers.
constexpr auto kCommandTimeout = 30000ms;
// How long the "offline" state may take to be acknowledged when the bridge stops.
constexpr auto kOfflineAckLimit = 2000ms;

std::string without_line_end(std::string line) {
  if (!line.empty() && line.back() == '\n') line.pop_back();
  return line;
}

}  // namespace

Bridge::Bridge(BridgeConfig config, const std::string& password)
    : config_(std::move(config)),
      topics_(config_),
      backoff_(config_.reconnect.initial),
      summary_(config_.publish.ranges_beam_step) {
  SessionCallbacks callbacks;
  callbacks.connected = [this] {
    // The retained online state, then the state topics again on the main thread.
    session_->publish({topics_.online(), kOnline, Qos::AtLeastOnce, true});
    republish_ = true;
  };
  callbacks.message = [this](std::string topic, std::string payload) {
    if (topic == topics_.command()) queue_command(std::move(payload));
  };
  session_ = std::make_unique<MqttSession>(
      config_.broker, config_.reconnect, password,
      Publication{topics_.online(), kOffline, Qos::AtLeastOnce, true}, std::move(callbacks));
  session_->subscribe(topics_.command(), Qos::AtLeastOnce);
}

Bridge::~Bridge() = default;

void Bridge::publish(const std::string& topic, std::string payload, Qos qos, bool retain) {
  if (session_->publish({topic, std::move(payload), qos, retain})) ++published_;
}

void Bridge::queue_command(std::string payload) {
  {
    const std::lock_guard lock(commands_mutex_);
    if (commands_.size() < kMaxQueuedCommands) {
      commands_.push_back(std::move(payload));
      commands_ready_.notify_one();
      return;
    }
  }
  // Too many waiting: answered here, on the network thread, without reading the command further.
  session_->publish({topics_.reply(),
                     without_line_end(ipc::socket::encode_error_reply(
                         std::nullopt, ipc::socket::ErrorCode::Unavailable,
                         "command: " + std::to_string(kMaxQueuedCommands) +
                             " commands are already waiting; try again")),
                     Qos::AtLeastOnce, false});
}

void Bridge::connect_tofcompd(Clock::time_point now) {
  if (stream_ || now < next_try_) return;
  try {
    client::Connection stream(config_.tofcompd_socket, kTofcompdTimeout);
    stream.subscribe(std::nullopt, 1, client::Format::Compact, kTofcompdTimeout);
    client::Connection control(config_.tofcompd_socket, kTofcompdTimeout);
    stream_.emplace(std::move(stream));
    control_.emplace(std::move(control));
    spdlog::info("tofcompd: reading {} (tofcompd {}, protocol {}.{})", config_.tofcompd_socket,
                 stream_->hello().daemon_version, stream_->hello().protocol_major,
                 stream_->hello().protocol_minor);
    tofcompd_error_.clear();
    backoff_ = config_.reconnect.initial;
    status_due_ = now;  // a fresh status at once
  } catch (const client::Error& e) {
    const std::string why = e.what();
    if (why != tofcompd_error_) {
      spdlog::warn("tofcompd: {}; trying again with backoff (at most {} s)", why,
                   config_.reconnect.max.count());
    }
    tofcompd_error_ = why;
    next_try_ = now + backoff_;
    backoff_ = std::min(backoff_ * 2, config_.reconnect.max);
  }
}

void Bridge::drop_tofcompd(const std::string& why, Clock::time_point now) {
  spdlog::warn("tofcompd: lost {} ({}); reconnecting", config_.tofcompd_socket, why);
  stream_.reset();
  control_.reset();
  tofcompd_error_ = why;
  last_status_ = nullptr;
  next_try_ = now + backoff_;
  status_due_ = now;  // say so on the status topic at once
}

void Bridge::on_scan(const client::Scan& scan, Clock::time_point now) {
  summary_.add(scan);
  if (now >= junction_due_) {
    publish(topics_.junction(), junction_payload(scan), Qos::AtMostOnce, false);
    junction_due_ = now + config_.publish.junction;
  }
  if (now >= ranges_due_) {
    if (summary_.scans() > 0) {
      nlohmann::ordered_json summary = summary_.take();
      last_flag_share_ = nlohmann::json::parse(summary["flag_share"].dump());
      summary["published_ns"] = realtime_ns();
      std::string payload = summary.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      if (payload.size() <= kMaxRangesPayloadBytes) {
        publish(topics_.ranges(), std::move(payload), Qos::AtMostOnce, false);
      } else {
        spdlog::warn("ranges: a summary of {} bytes is beyond the limit of {}; raise "
                     "publish.ranges_beam_step", payload.size(), kMaxRangesPayloadBytes);
      }
    }
    ranges_due_ = now + config_.publish.ranges;
  }
}

void Bridge::publish_status(Clock::time_point now) {
  status_due_ = now + config_.publish.status;
  std::string error = tofcompd_error_;
  if (control_) {
    try {
      const nlohmann::json reply =
          nlohmann::json::parse(control_->call(R"({"op":"status"})", kTofcompdTimeout));
      last_status_ = reply.at("status");
    } catch (const std::exception& e) {  // client::Error, or a reply without status
      drop_tofcompd(e.what(), now);
      error = tofcompd_error_;
    }
  }
  publish(topics_.status(), status_payload(last_status_, error), Qos::AtLeastOnce, true);
  if (last_status_.is_object()) {
    const auto id = last_status_.value("calibration", nlohmann::json::object()).value("id", 0u);
    if (!published_calibration_ || *published_calibration_ != id) {
      publish(topics_.calibration(), calibration_payload(last_status_), Qos::AtLeastOnce, true);
      published_calibration_ = id;
    }
  }
}

void Bridge::publish_diagnosis(Clock::time_point now) {
  diagnosis_due_ = now + config_.publish.diagnosis;
  publish(topics_.diagnosis(), diagnosis_payload(last_status_, last_flag_share_),
          Qos::AtLeastOnce, true);
}

void Bridge::serve_commands() {
  for (;;) {
    std::string payload;
    {
      const std::lock_guard lock(commands_mutex_);
      if (commands_.empty()) return;
      payload = std::move(commands_.front());
      commands_.pop_front();
    }
    const CommandDecision decision =
        decide_command(payload, config_.commands, config_.source);
    std::string reply = decision.refusal;
    if (decision.request) {
      const std::string op = decision.request->at("op");
      if (!control_) {
        reply = without_line_end(ipc::socket::encode_error_reply(
            decision.id, ipc::socket::ErrorCode::Unavailable,
            op + ": tofcompd cannot be reached: " + tofcompd_error_));
      } else {
        try {
          reply = relay_reply(decision.id, control_->call(decision.request->dump(), kCommandTimeout));
          spdlog::info("command: {} done", op);
        } catch (const client::Error& e) {
          if (e.kind() != client::ErrorKind::Daemon) {
            drop_tofcompd(e.what(), Clock::now());
            reply = without_line_end(ipc::socket::encode_error_reply(
                decision.id, ipc::socket::ErrorCode::Unavailable, op + ": " + e.what()));
          } else {
            const auto code = ipc::socket::error_code_from_string(e.daemon_code());
            reply = without_line_end(ipc::socket::encode_error_reply(
                decision.id, code.value_or(ipc::socket::ErrorCode::Internal), e.what()));
          }
        }
      }
    } else {
      spdlog::warn("command refused: {}", reply);
    }
    publish(topics_.reply(), std::move(reply), Qos::AtLeastOnce, false);
  }
}

void Bridge::idle(std::chrono::milliseconds limit) {
  std::unique_lock lock(commands_mutex_);
  commands_ready_.wait_for(lock, limit, [this] { return !commands_.empty(); });
}

void Bridge::run(const std::atomic<bool>& stop) {
  spdlog::info("bridge: {} to the broker at {}:{}{}; commands: reload {}, recalibrate {}",
               topics_.base, config_.broker.host, config_.broker.port,
               config_.broker.tls ? " (TLS)" : "", config_.commands.reload ? "allowed" : "refused",
               config_.commands.recalibrate ? "allowed" : "refused");
  session_->start();
  const Clock::time_point start = Clock::now();
  ranges_due_ = start + config_.publish.ranges;
  diagnosis_due_ = start + config_.publish.diagnosis;
  while (!stop) {
    Clock::time_point now = Clock::now();
    connect_tofcompd(now);
    if (republish_.exchange(false)) {
      published_calibration_.reset();
      publish_status(now);
      publish_diagnosis(now);
    }
    if (now >= status_due_) publish_status(now);
    if (now >= diagnosis_due_) publish_diagnosis(now);
    serve_commands();
    const auto until = std::min({status_due_, diagnosis_due_, now + kLoopSlice});
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(
        std::max(until - now, Clock::duration(1ms)));
    if (!stream_) {
      idle(wait);
      continue;
    }
    try {
      if (const auto scan = stream_->next_scan(wait)) on_scan(*scan, Clock::now());
    } catch (const client::Error& e) {
      drop_tofcompd(e.what(), Clock::now());
    }
  }
  spdlog::info("bridge: stopping after {} messages published; {} is now offline", published_,
               topics_.base);
  session_->stop({topics_.online(), kOffline, Qos::AtLeastOnce, true}, kOfflineAckLimit);
}

}  // namespace tofcomp::bridges::mqtt
