// The error codes of tofcompd's socket protocol (docs/protocol.md) and the exception that
// carries one: what the request parser throws, what the server turns into an error reply, and
// what the client library throws when the daemon answers with ok:false.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace tofcomp::ipc::socket {

enum class ErrorCode {
  BadRequest,   // not JSON, not an object, a field missing, of the wrong type, or unknown
  UnknownOp,    // "op" names no operation
  TooLong,      // the request line is longer than the server's limit; the server then closes
  BadRange,     // a number outside what the field allows, or beams outside the scan
  Unavailable,  // nothing to answer yet (no scan published), or too many clients
  Refused,      // the daemon declined the action (reload failed, recalibration not accepted)
  Internal,     // the daemon failed while answering
  Forbidden,    // the client may read but not control (reload, recalibrate): docs/protocol.md
};

// The wire name: bad_request, unknown_op, too_long, bad_range, unavailable, refused, internal,
// forbidden.
std::string_view to_string(ErrorCode code);
// The code of a wire name; nullopt for a name that is none of them.
std::optional<ErrorCode> error_code_from_string(std::string_view name);

class ProtocolError : public core::Error {
 public:
  // message names the field at fault first: "beams: first 10 is after last 5".
  // id is the request's id when it was read before the fault was found.
  ProtocolError(ErrorCode code, const std::string& message,
                std::optional<nlohmann::json> id = std::nullopt);

  ErrorCode code() const { return code_; }
  const std::optional<nlohmann::json>& id() const { return id_; }

 private:
  ErrorCode code_;
  std::optional<nlohmann::json> id_;
};

}  // namespace tofcomp::ipc::socket
