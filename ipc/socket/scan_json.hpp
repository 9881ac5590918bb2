// A CompensatedScan as the JSON object of the socket protocol (docs/protocol.md): every field of
// the scan, the beams of one range as objects, a value that does not exist (NaN, or infinite) as
// null, the flags as the number and as a list of names. Written directly, not through a DOM:
// this is the daemon's hot path, run once per scan for each distinct beam range subscribed.
// The one JSON form of a scan: tofcompd's socket, `tofcomp query` and `tofcomp shm-dump` print
// it; decode_scan() reads it back for a client.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "ipc/compensated_scan.hpp"
#include "ipc/socket/request.hpp"

namespace tofcomp::ipc::socket {

// The beams [first, first + count) of a scan.
struct BeamSpan {
  std::size_t first = 0;
  std::size_t count = 0;
  bool operator==(const BeamSpan&) const = default;
};

// The span a request asks for (every beam when wanted is absent). Throws ProtocolError
// bad_range when the range reaches beyond the scan's beam_count beams.
BeamSpan beams_exactly(const std::optional<BeamRange>& wanted, std::size_t beam_count);

// The part of the wanted range that the scan has: what a subscription receives when a scan is
// narrower than its range (count 0 when first is beyond the scan).
BeamSpan beams_clipped(const std::optional<BeamRange>& wanted, std::size_t beam_count);

// The scan as one JSON object (no newline). span must lie within scan.beams.
std::string encode_scan(const ipc::CompensatedScan& scan, BeamSpan span);

// A scan as a client receives it: the scan with beam_count beams, of which those of span hold
// what was sent (the others are default values).
struct ReceivedScan {
  ipc::CompensatedScan scan;
  BeamSpan span;
};

// The scan object encode_scan() wrote, read back (null as NaN). Throws core::InvalidInput
// naming what is wrong when the object is not one.
ReceivedScan decode_scan(const nlohmann::json& object);

}  // namespace tofcomp::ipc::socket
