// One connection to an MQTT broker through libmosquitto (MQTT 3.1.1): TLS and credentials from
// the configuration, a last will set before the first connect (so that it holds across every
// reconnect), libmosquitto's network thread with its exponential reconnect backoff, and the
// subscriptions made again on each connect. Publishing is allowed from any thread; messages
// and the connect event are handed to the callbacks on the network thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "bridges/mqtt/bridge_config.hpp"

struct mosquitto;
struct mosquitto_message;

namespace tofcomp::bridges::mqtt {

// QoS 0: at most once (telemetry that the next period replaces); QoS 1: at least once (state
// and replies, which must arrive). QoS 2 costs two more round trips and is not used.
enum class Qos { AtMostOnce = 0, AtLeastOnce = 1 };

struct Publication {
  std::string topic;
  std::string payload;
  Qos qos = Qos::AtMostOnce;
  bool retain = false;
};

struct SessionCallbacks {
  std::function<void()> connected;                                  // after each CONNACK accepted
  std::function<void(std::string topic, std::string payload)> message;  // a subscribed message
};

class MqttSession {
 public:
  // Sets up the client (nothing is sent yet). Throws core::InvalidInput when libmosquitto refuses
  // a setting (a TLS file it cannot use, a client id it rejects), naming it.
  MqttSession(const BrokerSettings& broker, const Backoff& backoff, const std::string& password,
              Publication will, SessionCallbacks callbacks);
  ~MqttSession();
  MqttSession(const MqttSession&) = delete;
  MqttSession& operator=(const MqttSession&) = delete;

  // Subscribes now (when connected) and after every connect.
  void subscribe(const std::string& topic, Qos qos);
  // Starts connecting (in the background, retrying with backoff until stop()).
  void start();
  // Queues a message; false (and nothing queued) while not connected, so that telemetry never
  // piles up in memory during an outage: state topics are published again on connect.
  bool publish(const Publication& message);
  bool connected() const { return connected_.load(); }
  // Publishes `last` (the "offline" state: a clean DISCONNECT does not fire the will), waits up to
  // `limit` for the broker to acknowledge it, disconnects and stops the network thread.
  void stop(const Publication& last, std::chrono::milliseconds limit);

 private:
  static void on_connect(mosquitto*, void* self, int rc);
  static void on_disconnect(mosquitto*, void* self, int rc);
  static void on_publish(mosquitto*, void* self, int mid);
  static void on_message(mosquitto*, void* self, const mosquitto_message* message);
  static void on_log(mosquitto*, void* self, int level, const char* text);

  std::string host_;
  int port_ = 0;
  int keepalive_s_ = 0;
  std::string where_;  // "host:port", for messages
  SessionCallbacks callbacks_;
  mosquitto* client_ = nullptr;
  std::atomic<bool> connected_{false};
  std::atomic<bool> stopping_{false};
  bool started_ = false;
  std::mutex mutex_;
  std::condition_variable acknowledged_;
  std::set<int> acknowledged_ids_;
  std::vector<std::pair<std::string, Qos>> subscriptions_;
};

}  // namespace tofcomp::bridges::mqtt
