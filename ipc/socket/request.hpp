// A request of tofcompd's socket protocol (docs/protocol.md) and its parser: one line of JSON
// in, a Request out, or a ProtocolError whose message names the field at fault.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "ipc/socket/protocol_constants.hpp"
#include "ipc/socket/protocol_error.hpp"

namespace tofcomp::ipc::socket {

enum class Op { Latest, Subscribe, Unsubscribe, Status, Stats, Reload, Recalibrate, Hello };

// The wire name: latest, subscribe, unsubscribe, status, stats, reload, recalibrate, hello.
std::string_view to_string(Op op);

// An inclusive range of beam indices, first <= last.
struct BeamRange {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  bool operator==(const BeamRange&) const = default;
};

// How a subscription's scans are sent: JSON lines, or compact binary frames
// (ipc/socket/compact_frame.hpp).
enum class ScanFormat { Json, Compact };

// The wire name: json, compact.
std::string_view to_string(ScanFormat format);

struct Request {
  Op op = Op::Status;
  std::optional<nlohmann::json> id;  // a string or an integer, echoed in the reply
  std::optional<BeamRange> beams;    // latest, subscribe: absent means every beam
  std::uint32_t every = 1;           // subscribe: scans whose sequence is a multiple of this
  ScanFormat format = ScanFormat::Json;  // subscribe: how the scans are sent
  nlohmann::json args = nlohmann::json::object();  // recalibrate: passed to the daemon as is
};

// Parses one request line (without its '\n'). Throws ProtocolError: too_long when the line has
// more than max_bytes bytes, bad_request / unknown_op / bad_range otherwise, carrying the id
// when the line had a valid one. Throws nothing else.
Request parse_request(std::string_view line, std::size_t max_bytes = kDefaultMaxRequestBytes);

}  // namespace tofcomp::ipc::socket
