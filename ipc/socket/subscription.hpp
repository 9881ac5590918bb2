// A subscription to tofcompd's scans over a SocketClient: subscribe, then read one scan at a
// time with a timeout (docs/protocol.md, "subscribe").
#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>

#include "ipc/socket/client.hpp"
#include "ipc/socket/request.hpp"

namespace tofcomp::ipc::socket {

class ScanSubscription {
 public:
  using Duration = std::chrono::milliseconds;

  // Sends subscribe (beams absent: every beam) and waits for the acknowledgement. Throws
  // ProtocolError when the daemon refuses it, core::Error when it does not answer in time.
  // client must outlive the subscription.
  ScanSubscription(SocketClient& client, std::optional<BeamRange> beams, std::uint32_t every,
                   Duration timeout);

  // The next scan (the "scan" object of a scan event); nullopt when none came within timeout.
  // Throws core::Error when a line other than a scan event arrives, SocketClosed when the
  // daemon closed the connection (it drops a client that does not keep up).
  std::optional<nlohmann::json> next(Duration timeout);

  // Sends unsubscribe and waits for its reply. Scans sent before it stay readable with the
  // client's read_message.
  void unsubscribe(Duration timeout);

  // What the daemon acknowledged: {"beams": [first, last] or null, "every": N}.
  const nlohmann::json& acknowledged() const { return acknowledged_; }

 private:
  SocketClient& client_;
  nlohmann::json acknowledged_;
};

}  // namespace tofcomp::ipc::socket
