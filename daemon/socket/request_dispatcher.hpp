// Answers one request line of a connection: parses it, asks the daemon's handler, encodes the
// reply, and keeps the connection's subscription. No I/O: the server writes what it returns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "daemon/socket/request_handler.hpp"
#include "ipc/socket/request.hpp"

namespace tofcomp::daemon::socket {

// What a connection subscribed to: scans whose sequence is a multiple of every, these beams.
struct Subscription {
  std::optional<ipc::socket::BeamRange> beams;  // absent: every beam
  std::uint32_t every = 1;
  ipc::socket::ScanFormat format = ipc::socket::ScanFormat::Json;
};

struct Answer {
  std::string line;        // the reply, '\n' terminated
  bool error = false;      // the reply is ok:false
  bool close = false;      // the connection is to be closed once the reply is written (too_long)
  bool forbidden = false;  // a control request from a caller not allowed to control
};

// Who sent the line, as far as the answer depends on it.
struct Caller {
  bool may_control = false;  // reload and recalibrate are answered (else: forbidden)
  std::string peer;          // "uid 1001 (alice), pid 4242": named in a refusal
  std::string controllers;   // "uid 0 (root) and uid 999 (tofcompd)": who may control
};

class RequestDispatcher {
 public:
  using CountersJson = std::function<nlohmann::ordered_json()>;

  // socket_counters gives the server's counters for the "socket" member of the stats reply.
  RequestDispatcher(SocketRequestHandler& handler, std::size_t max_request_bytes,
                    CountersJson socket_counters);

  // The reply to one line (without its '\n'); subscribe and unsubscribe change subscription.
  // Never throws: a failure of the handler is an error reply. A control request (reload,
  // recalibrate) from a caller who may not control is answered forbidden, the handler unasked.
  Answer answer(std::string_view line, std::optional<Subscription>& subscription,
                const Caller& caller);

 private:
  SocketRequestHandler& handler_;
  std::size_t max_request_bytes_;
  CountersJson socket_counters_;

  std::string execute(const ipc::socket::Request& request,
                      std::optional<Subscription>& subscription);
};

}  // namespace tofcomp::daemon::socket
