// The numbers of tofcompd's socket protocol (docs/protocol.md): where the socket is by default
// and the limits a request must keep to.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tofcomp::ipc::socket {

// The protocol's version, which the hello reply states (docs/protocol.md, "hello"). A minor
// version adds ops or fields and changes none; a client refuses a daemon whose major differs.
inline constexpr int kProtocolVersionMajor = 1;
inline constexpr int kProtocolVersionMinor = 0;

inline constexpr const char* kDefaultSocketPath = "/run/tofcompd/tofcompd.sock";
inline constexpr std::size_t kDefaultMaxRequestBytes = 4096;  // one request line, '\n' excluded
inline constexpr std::size_t kMaxIdBytes = 256;               // a string id
inline constexpr std::uint32_t kMaxBeamIndex = 65535;         // beams: indices 0..65535
inline constexpr std::uint32_t kMaxEvery = 1000000;           // subscribe: every 1..1000000
// Objects and arrays nested in one request at most: no request of the protocol needs more than
// three levels; the bound keeps a hostile line (200,000 '[' fit in the largest allowed
// max_request_bytes) from recursing through the JSON value's copy and destruction.
inline constexpr int kMaxRequestDepth = 32;

}  // namespace tofcomp::ipc::socket
