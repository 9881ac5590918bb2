// tofcompd's Unix-socket server (docs/protocol.md): line-delimited JSON requests answered
// through the daemon's SocketRequestHandler, and every published scan fanned out to the
// subscribed connections. Single-threaded on the daemon's io_context and never blocking: each
// connection has a write queue bounded in bytes, and a connection whose queue of scans would
// exceed the bound (its client is not reading) is dropped without delaying anyone else. A
// connection's requests wait while its queue is over half the bound (back-pressure), so replies
// never overflow it. Control requests (reload, recalibrate) are answered only for the users the
// settings allow (by SO_PEERCRED), who also get one slot beyond max_clients; a connection that
// sends no request and is delivered nothing for idle_timeout is closed.
#pragma once

#include <sys/types.h>

#include <boost/asio.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "daemon/socket/request_handler.hpp"
#include "ipc/compensated_scan.hpp"
#include "ipc/socket/request.hpp"
#include "ipc/socket/server_defaults.hpp"

namespace tofcomp::daemon::socket {

// The defaults are ipc/socket/server_defaults.hpp's, the configuration's (outputs.socket.*).
struct SocketServerSettings {
  std::string path = ipc::socket::kDefaultSocketPath;
  unsigned permissions = ipc::socket::kDefaultSocketMode;  // of the socket file
  std::size_t max_clients = ipc::socket::kDefaultMaxClients;
  std::size_t max_request_bytes = ipc::socket::kDefaultMaxRequestBytes;
  std::size_t max_queued_bytes_per_client = ipc::socket::kDefaultMaxQueuedBytesPerClient;
  std::chrono::milliseconds idle_timeout = ipc::socket::kDefaultIdleTimeout;
  // The users whose connections may send control requests (reload, recalibrate), by the peer's
  // credentials. Empty: the server's own effective user and root.
  std::vector<uid_t> control_uids;
  // A listening Unix stream socket the service manager passed (socket activation,
  // daemon/service/socket_activation.hpp), bound to `path`: served instead of binding one. The
  // server serves on a duplicate and leaves the socket file to the manager: it neither makes,
  // chmods nor removes it (the manager's SocketMode= sets its permissions).
  std::optional<int> activated_listener;

  void validate() const;  // throws core::InvalidInput naming the setting at fault
};

struct SocketServerCounters {
  std::uint64_t clients = 0;               // connected now, the operator's slot included
  std::uint64_t subscribers = 0;           // of those, subscribed now
  std::uint64_t accepted_clients = 0;      // admitted since start
  std::uint64_t refused_clients = 0;       // turned away at max_clients
  std::uint64_t dropped_slow_clients = 0;  // closed because their queue was full
  std::uint64_t idle_clients_closed = 0;   // closed after idle_timeout: no request, nothing sent
  std::uint64_t forbidden_requests = 0;    // control requests from users not allowed them
  std::uint64_t requests = 0;              // request lines answered
  std::uint64_t errors = 0;                // of those, answered with an error
  std::uint64_t scans_published = 0;       // publish() calls while running
  std::uint64_t scan_encodings = 0;        // scans encoded (once per distinct beam range)
  std::uint64_t queued_bytes = 0;          // queued now, summed over connections
  std::uint64_t peak_queued_bytes = 0;     // the most queued_bytes has been
  std::uint64_t peak_client_queued_bytes = 0;  // the most one connection has had queued
};

nlohmann::ordered_json to_json(const SocketServerCounters& counters);

enum class SocketLogLevel { Info, Warning };
using SocketLog = std::function<void(SocketLogLevel, const std::string& message)>;

class SocketServer {
 public:
  // Throws core::InvalidInput for bad settings. handler must outlive the server; log may be
  // empty. Every member is to be called on io's thread.
  SocketServer(boost::asio::io_context& io, SocketServerSettings settings,
               SocketRequestHandler& handler, SocketLog log = {});
  ~SocketServer();  // stop()
  SocketServer(const SocketServer&) = delete;
  SocketServer& operator=(const SocketServer&) = delete;

  // Claims the path (a stale socket file is removed only when nothing listens on it), binds,
  // sets the permissions and listens; or serves the activated listener. Throws core::Error
  // naming the path when another daemon listens there, the path holds something else, or
  // binding fails.
  void start();
  // Closes every connection and the listener and removes the socket file (if it is still the
  // one start() made). The server may be destroyed at once.
  void stop();

  // Sends scan to every subscribed connection that takes it; never blocks.
  void publish(const ipc::CompensatedScan& scan);

  SocketServerCounters counters() const;
  const SocketServerSettings& settings() const;
  bool running() const;

 private:
  class Impl;
  std::shared_ptr<Impl> impl_;
};

}  // namespace tofcomp::daemon::socket
