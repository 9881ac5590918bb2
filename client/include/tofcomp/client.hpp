// libtofcomp-client's C++ API: read tofcompd's compensated scans from its Unix socket
// (docs/protocol.md) or its shared-memory ring (docs/shm-ring.md). A Connection exchanges hello
// when it connects and refuses a daemon of another major protocol version; a Ring reads the
// scans the daemon publishes to shared memory, with the writer's torn copies discarded. The scan
// types are those of the C API (tofcomp/tofcomp_client.h). Not thread-safe: one thread per
// Connection or Ring. Every failure throws tofcomp::client::Error.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tofcomp/tofcomp_client.h"

namespace tofcomp::client {

using Beam = ::tofcomp_beam;
using ScanInfo = ::tofcomp_scan_info;

// A scan as received: its header, the beams carried (a contiguous range of indices; every beam
// unless fewer were asked for), and for a scan that came as JSON the scan object as sent.
struct Scan {
  ScanInfo info{};
  std::vector<Beam> beams;
  std::string json;  // empty for a compact frame or a scan read from the ring
};

// What kind of failure an Error is: the C API's status (TOFCOMP_ERR_*).
enum class ErrorKind {
  InvalidArgument = TOFCOMP_ERR_INVALID_ARGUMENT,
  Connect = TOFCOMP_ERR_CONNECT,
  ProtocolVersion = TOFCOMP_ERR_PROTOCOL_VERSION,
  Timeout = TOFCOMP_ERR_TIMEOUT,
  Closed = TOFCOMP_ERR_CLOSED,
  Daemon = TOFCOMP_ERR_DAEMON,
  BadData = TOFCOMP_ERR_BAD_DATA,
  Ring = TOFCOMP_ERR_RING,
  Internal = TOFCOMP_ERR_INTERNAL,
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message, std::string daemon_code = {});
  ErrorKind kind() const { return kind_; }
  // For ErrorKind::Daemon: the daemon's error code (bad_range, unavailable, forbidden, ...).
  const std::string& daemon_code() const { return daemon_code_; }

 private:
  ErrorKind kind_;
  std::string daemon_code_;
};

// What the daemon's hello stated.
struct Hello {
  int protocol_major = 0;
  int protocol_minor = 0;
  std::string daemon;          // "tofcompd"
  std::string daemon_version;  // "0.1.0"
};

enum class Format { Json = TOFCOMP_FORMAT_JSON, Compact = TOFCOMP_FORMAT_COMPACT };

// An inclusive range of beam indices.
struct BeamRange {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
};

// The library's version as linked ("0.1.0").
const char* library_version();

// The names of the set flag bits, lowest first ("no_echo", ...; "bitN" for a bit without one).
std::vector<std::string> flag_names(std::uint16_t flags);

// Decodes one compact frame (docs/protocol.md, "Compact frames"). Throws Error (BadData).
Scan decode_compact(const void* bytes, std::size_t size);

// The socket and the ring a program reads when it names none, as `tofcomp query` and `tofcomp
// shm-dump` choose them (docs/deployment.md, "As an ordinary user"): for a user other than root,
// that user's own daemon's ($XDG_RUNTIME_DIR/tofcompd/tofcompd.sock, the ring /tofcompd.UID)
// when it runs; the system's (TOFCOMP_DEFAULT_SOCKET_PATH, TOFCOMP_DEFAULT_RING_NAME) otherwise.
std::string default_socket_path();
std::string default_ring_name();

class Connection {
 public:
  using Duration = std::chrono::milliseconds;
  static constexpr Duration kDefaultTimeout{5000};

  // Connects and exchanges hello (both within timeout). Throws Error: Connect, ProtocolVersion
  // (naming the daemon's version and this library's), Timeout, Closed.
  explicit Connection(const std::string& path = default_socket_path(),
                      Duration timeout = kDefaultTimeout);
  ~Connection();
  Connection(Connection&&) noexcept;
  Connection& operator=(Connection&&) noexcept;

  const Hello& hello() const;
  const std::string& path() const;

  // The latest scan (every beam when beams is absent). Throws Error (Daemon "unavailable"
  // before the first scan, "bad_range" for beams beyond the scan).
  Scan latest(std::optional<BeamRange> beams = std::nullopt, Duration timeout = kDefaultTimeout);

  // Subscribes (replacing any subscription of this connection) to the scans whose sequence is a
  // multiple of every, these beams (all when absent), as JSON or compact frames.
  void subscribe(std::optional<BeamRange> beams = std::nullopt, std::uint32_t every = 1,
                 Format format = Format::Json, Duration timeout = kDefaultTimeout);
  // The next scan of the subscription; nullopt when none came within timeout. Throws Error
  // (Closed when the daemon closed the connection, e.g. because this client fell behind).
  std::optional<Scan> next_scan(Duration timeout);
  void unsubscribe(Duration timeout = kDefaultTimeout);

  // Any request (a JSON object as text; an "id" is added when it has none) and the reply line.
  // Throws Error (Daemon, with the daemon's code) when the daemon answers with an error.
  std::string call(const std::string& request_json, Duration timeout = kDefaultTimeout);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class Ring {
 public:
  // Opens the ring read-only, checking its owner (this user, root or tofcompd) and its header.
  // Throws Error (Ring) naming the ring and the reason. Reading starts at the next scan.
  explicit Ring(const std::string& name = default_ring_name());
  ~Ring();
  Ring(Ring&&) noexcept;
  Ring& operator=(Ring&&) noexcept;

  // The newest scan; nullopt while none was published.
  std::optional<Scan> latest();
  // The next scan since the last one returned, oldest first; nullopt when none is new.
  std::optional<Scan> next();
  // Scans overwritten before this reader copied them, since it was opened.
  std::uint64_t lost() const;
  // The ring read (the name asked for, or where tofcompd publishes when another user holds it).
  const std::string& name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tofcomp::client
