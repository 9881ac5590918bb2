// What tofcompd's socket server asks of the daemon (docs/protocol.md): the latest scan, status
// and statistics, and the two actions. Implemented by the daemon; every call is made on the
// server's io_context thread and must not block.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "ipc/compensated_scan.hpp"

namespace tofcomp::daemon::socket {

struct ReloadResult {
  bool ok = false;
  std::string message;  // what was reloaded, or why not
};

struct RecalibrationResult {
  bool accepted = false;
  std::string message;  // what will happen, or why not
};

// A handler may throw ipc::socket::ProtocolError to answer with a code of its choice,
// core::InvalidInput to answer bad_request (its message naming the field, e.g. "args.x: ..."),
// anything else to answer internal. The server never lets an exception through.
class SocketRequestHandler {
 public:
  virtual ~SocketRequestHandler() = default;

  // The latest scan published; nullptr before the first. The server encodes it at once and
  // keeps no pointer.
  virtual const ipc::CompensatedScan* latest_scan() = 0;
  // The daemon's state (an object), sent as the "status" member of the reply.
  virtual nlohmann::json status() = 0;
  // The daemon's counters (an object), sent as the "stats" member of the reply.
  virtual nlohmann::json stats() = 0;
  // Re-reads configuration and calibration; ok false makes a "refused" reply with message.
  virtual ReloadResult reload() = 0;
  // Starts a recalibration; args is the request's "args" object ({} when absent).
  virtual RecalibrationResult recalibrate(const nlohmann::json& args) = 0;
};

}  // namespace tofcomp::daemon::socket
