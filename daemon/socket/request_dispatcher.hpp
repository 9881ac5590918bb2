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
};

struct Answer {
  std::string line;    // the reply, '\n' terminated
  bool error = false;  // the reply is ok:false
  bool close = false;  // the connection is to be closed once the reply is written (too_long)
};

class RequestDispatcher {
 public:
  using CountersJson = std::function<nlohmann::ordered_json()>;

  // socket_counters gives the server's counters for the "socket" member of the stats reply.
  RequestDispatcher(SocketRequestHandler& handler, std::size_t max_request_bytes,
                    CountersJson socket_counters);

  // The reply to one line (without its '\n'); subscribe and unsubscribe change subscription.
  // Never throws: a failure of the handler is an error reply.
  Answer answer(std::string_view line, std::optional<Subscription>& subscription);

 private:
  SocketRequestHandler& handler_;
  std::size_t max_request_bytes_;
  CountersJson socket_counters_;

  std::string execute(const ipc::socket::Request& request,
                      std::optional<Subscription>& subscription);
};

}  // namespace tofcomp::daemon::socket
