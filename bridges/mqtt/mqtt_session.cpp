// libmosquitto behind MqttSession: its callbacks land here on its network thread.
#include "bridges/mqtt/mqtt_session.hpp"

#include <mosquitto.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstring>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::bridges::mqtt {

namespace {

// libmosquitto's global state (OpenSSL among it), set up once for the process.
void initialise_library() {
  static const int kInitialised = [] {
    mosquitto_lib_init();
    return 0;
  }();
  (void)kInitialised;
}

// Messages in flight (QoS 1, not yet acknowledged) at once: the bridge publishes a few a second.
constexpr unsigned kMaxInflightMessages = 32;

void check(int rc, const std::string& what) {
  if (rc != MOSQ_ERR_SUCCESS) {
    const std::string reason =
        rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : std::string(mosquitto_strerror(rc));
    throw core::InvalidInput(what + ": " + reason);
  }
}

}  // namespace

MqttSession::MqttSession(const BrokerSettings& broker, const Backoff& backoff,
                         const std::string& password, Publication will, SessionCallbacks callbacks)
    : host_(broker.host),
      port_(broker.port),
      keepalive_s_(static_cast<int>(broker.keepalive.count())),
      where_(broker.host + ":" + std::to_string(broker.port)),
      callbacks_(std::move(callbacks)) {
  initialise_library();
  // A clean session: commands sent while the bridge was away are not delivered late.
  client_ = mosquitto_new(broker.client_id.c_str(), true, this);
  if (!client_) throw core::InvalidInput("broker.client_id '" + broker.client_id + "': refused");
  check(mosquitto_int_option(client_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311),
        "MQTT 3.1.1");
  check(mosquitto_max_inflight_messages_set(client_, kMaxInflightMessages), "inflight messages");
  check(mosquitto_reconnect_delay_set(client_, static_cast<unsigned>(backoff.initial.count()),
                                      static_cast<unsigned>(backoff.max.count()), true),
        "reconnect");
  check(mosquitto_will_set(client_, will.topic.c_str(), static_cast<int>(will.payload.size()),
                           will.payload.data(), static_cast<int>(will.qos), will.retain),
        "last will on " + will.topic);
  if (broker.username) {
    check(mosquitto_username_pw_set(client_, broker.username->c_str(),
                                    password.empty() ? nullptr : password.c_str()),
          "broker.username");
  }
  if (broker.tls) {
    const TlsSettings& tls = *broker.tls;
    const std::string cert = tls.cert_file ? tls.cert_file->string() : std::string();
    const std::string key = tls.key_file ? tls.key_file->string() : std::string();
    check(mosquitto_tls_set(client_, tls.ca_file.c_str(), nullptr,
                            tls.cert_file ? cert.c_str() : nullptr,
                            tls.key_file ? key.c_str() : nullptr, nullptr),
          "broker.tls (ca_file " + tls.ca_file.string() +
              (tls.cert_file ? ", cert_file " + cert + ", key_file " + key : std::string()) + ")");
    // The broker's chain is always checked against ca_file (SSL_VERIFY_PEER); verify_hostname
    // decides whether its certificate must also name the host.
    check(mosquitto_tls_opts_set(client_, 1, nullptr, nullptr), "broker.tls");
    check(mosquitto_tls_insecure_set(client_, !tls.verify_hostname), "broker.tls.verify_hostname");
  }
  mosquitto_connect_callback_set(client_, &MqttSession::on_connect);
  mosquitto_disconnect_callback_set(client_, &MqttSession::on_disconnect);
  mosquitto_publish_callback_set(client_, &MqttSession::on_publish);
  mosquitto_message_callback_set(client_, &MqttSession::on_message);
  mosquitto_log_callback_set(client_, &MqttSession::on_log);
}

MqttSession::~MqttSession() {
  if (started_) mosquitto_loop_stop(client_, true);
  mosquitto_destroy(client_);
}

void MqttSession::subscribe(const std::string& topic, Qos qos) {
  {
    const std::lock_guard lock(mutex_);
    subscriptions_.emplace_back(topic, qos);
  }
  if (connected_) mosquitto_subscribe(client_, nullptr, topic.c_str(), static_cast<int>(qos));
}

void MqttSession::start() {
  // A first connect that fails (no broker yet) is retried by the network thread.
  const int rc = mosquitto_connect_async(client_, host_.c_str(), port_, keepalive_s_);
  if (rc != MOSQ_ERR_SUCCESS) {
    spdlog::warn("mqtt: cannot reach the broker at {} yet ({}); retrying", where_,
                 rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc));
  }
  check(mosquitto_loop_start(client_), "the network thread");
  started_ = true;
}

bool MqttSession::publish(const Publication& message) {
  if (!connected_) return false;
  const int rc = mosquitto_publish(client_, nullptr, message.topic.c_str(),
                                   static_cast<int>(message.payload.size()),
                                   message.payload.data(), static_cast<int>(message.qos),
                                   message.retain);
  if (rc != MOSQ_ERR_SUCCESS) {
    spdlog::debug("mqtt: {} not published: {}", message.topic, mosquitto_strerror(rc));
    return false;
  }
  return true;
}

void MqttSession::stop(const Publication& last, std::chrono::milliseconds limit) {
  stopping_ = true;
  if (!started_) return;
  if (connected_) {
    int mid = 0;
    if (mosquitto_publish(client_, &mid, last.topic.c_str(), static_cast<int>(last.payload.size()),
                          last.payload.data(), static_cast<int>(last.qos),
                          last.retain) == MOSQ_ERR_SUCCESS) {
      std::unique_lock lock(mutex_);
      if (!acknowledged_.wait_for(lock, limit, [&] { return acknowledged_ids_.count(mid) != 0; })) {
        spdlog::warn("mqtt: the broker did not acknowledge {} within {} ms", last.topic,
                     limit.count());
      }
    }
    mosquitto_disconnect(client_);
    mosquitto_loop_stop(client_, false);
  } else {
    // Between tries the network thread may be asleep for the backoff: do not wait for it.
    mosquitto_disconnect(client_);
    mosquitto_loop_stop(client_, true);
  }
  started_ = false;
}

void MqttSession::on_connect(mosquitto*, void* self, int rc) {
  auto& session = *static_cast<MqttSession*>(self);
  if (rc != 0) {
    // CONNACK refused: bad credentials, not authorised, client id rejected. libmosquitto tries
    // again after the backoff (a broker's password file may be fixed without restarting us).
    spdlog::error("mqtt: the broker at {} refused the connection: {} (check broker.username, "
                  "broker.password_file and the broker's ACL)",
                  session.where_, mosquitto_connack_string(rc));
    return;
  }
  spdlog::info("mqtt: connected to the broker at {}", session.where_);
  session.connected_ = true;
  std::vector<std::pair<std::string, Qos>> subscriptions;
  {
    const std::lock_guard lock(session.mutex_);
    subscriptions = session.subscriptions_;
  }
  for (const auto& [topic, qos] : subscriptions) {
    mosquitto_subscribe(session.client_, nullptr, topic.c_str(), static_cast<int>(qos));
  }
  if (session.callbacks_.connected) session.callbacks_.connected();
}

void MqttSession::on_disconnect(mosquitto*, void* self, int rc) {
  auto& session = *static_cast<MqttSession*>(self);
  const bool was_connected = session.connected_.exchange(false);
  if (rc != 0 && !session.stopping_ && was_connected) {
    spdlog::warn("mqtt: lost the broker at {} ({}); reconnecting with backoff", session.where_,
                 mosquitto_strerror(rc));
  }
}

void MqttSession::on_publish(mosquitto*, void* self, int mid) {
  auto& session = *static_cast<MqttSession*>(self);
  {
    const std::lock_guard lock(session.mutex_);
    if (session.stopping_) session.acknowledged_ids_.insert(mid);
  }
  session.acknowledged_.notify_all();
}

void MqttSession::on_message(mosquitto*, void* self, const mosquitto_message* message) {
  auto& session = *static_cast<MqttSession*>(self);
  if (!session.callbacks_.message || !message->topic) return;
  const auto* bytes = static_cast<const char*>(message->payload);
  session.callbacks_.message(message->topic,
                             bytes ? std::string(bytes, static_cast<std::size_t>(message->payloadlen))
                                   : std::string());
}

void MqttSession::on_log(mosquitto*, void* self, int level, const char* text) {
  const auto& session = *static_cast<const MqttSession*>(self);
  // libmosquitto says here why a TLS handshake or a connect failed ("OpenSSL Error[0]: ...
  // certificate verify failed"); its routine traffic stays at debug.
  if (level == MOSQ_LOG_ERR) {
    spdlog::error("mqtt: {}: {}", session.where_, text);
  } else if (level == MOSQ_LOG_WARNING) {
    spdlog::warn("mqtt: {}: {}", session.where_, text);
  } else {
    spdlog::debug("mqtt: {}: {}", session.where_, text);
  }
}

}  // namespace tofcomp::bridges::mqtt
