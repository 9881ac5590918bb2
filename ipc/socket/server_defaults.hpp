// The settings of tofcompd's socket server (docs/protocol.md, "Limits"): each default and each
// bound in one place, which both the configuration reader (settings/, `outputs.socket.*`) and the
// server (daemon/socket/) take, so that the two can never disagree.
#pragma once

#include <chrono>
#include <cstddef>

namespace tofcomp::ipc::socket {

inline constexpr unsigned kDefaultSocketMode = 0660;  // the socket file: owner and group connect

inline constexpr std::size_t kDefaultMaxClients = 16;  // connections served at once
inline constexpr std::size_t kLargestMaxClients = 1024;

// The request line's limit (the default, kDefaultMaxRequestBytes, is in protocol_constants.hpp).
inline constexpr std::size_t kSmallestMaxRequestBytes = 64;
inline constexpr std::size_t kLargestMaxRequestBytes = 1u << 20;

// Output queued for one client: about 12 full LMS 200 scans by default.
inline constexpr std::size_t kDefaultMaxQueuedBytesPerClient = 1u << 20;
inline constexpr std::size_t kSmallestMaxQueuedBytesPerClient = 4096;
inline constexpr std::size_t kLargestMaxQueuedBytesPerClient = 1u << 30;

// A connection that sends no request and is delivered nothing for this long is closed, so that
// silent clients cannot hold every slot.
inline constexpr std::chrono::seconds kDefaultIdleTimeout{60};
inline constexpr std::chrono::seconds kLargestIdleTimeout{86400};

}  // namespace tofcomp::ipc::socket
