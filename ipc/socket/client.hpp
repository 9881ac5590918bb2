// A blocking client of tofcompd's Unix socket (docs/protocol.md) for `tofcomp query` and the
// tests: connect with a timeout, send request lines, read reply and event lines with a timeout,
// and request(), which sends one request and waits for its reply. Plain POSIX sockets; not
// thread-safe (one thread per client).
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "ipc/socket/protocol_constants.hpp"

namespace tofcomp::ipc::socket {

inline constexpr std::size_t kClientMaxLineBytes = 64u << 20;  // a line the client accepts

// One message from the daemon: a JSON line (a reply or a scan event), or a compact scan frame
// (ipc/socket/compact_frame.hpp) of a subscription with "format": "compact".
struct Message {
  nlohmann::json json;  // the line, parsed; null for a frame
  std::string frame;    // the frame's bytes; empty for a line
  bool is_frame() const { return !frame.empty(); }
};

// The daemon closed the connection (end of file or reset).
class SocketClosed : public core::Error {
 public:
  using core::Error::Error;
};

// No answer, or no room to write, within the timeout.
class SocketTimeout : public core::Error {
 public:
  using core::Error::Error;
};

class SocketClient {
 public:
  using Duration = std::chrono::milliseconds;

  // Throws core::Error naming the path and the reason: "cannot connect to
  // /run/tofcompd/tofcompd.sock: No such file or directory; is tofcompd running?".
  SocketClient(const std::string& path, Duration timeout);
  ~SocketClient();
  SocketClient(SocketClient&& other) noexcept;
  SocketClient& operator=(SocketClient&& other) noexcept;
  SocketClient(const SocketClient&) = delete;
  SocketClient& operator=(const SocketClient&) = delete;

  // Writes line and a '\n' (line must not contain one). Throws SocketTimeout when the daemon
  // does not take the bytes within timeout, SocketClosed when it has closed.
  void send_line(std::string_view line, Duration timeout = std::chrono::seconds(5));
  // Writes bytes as they are, no '\n' added: for tests of the framing.
  void send_bytes(std::string_view bytes, Duration timeout = std::chrono::seconds(5));

  // The next line without its '\n'; nullopt when none is complete within timeout. Throws
  // SocketClosed at the end of the stream, core::Error for a line beyond kClientMaxLineBytes
  // or a compact frame.
  std::optional<std::string> read_line(Duration timeout);
  // The next line parsed: a message kept aside by request() first. Throws core::Error when the
  // line is not JSON or a compact frame comes instead.
  std::optional<nlohmann::json> read_message(Duration timeout);
  // The next message, line or compact frame: one kept aside by request() first. Throws
  // core::Error when a line is not JSON or a frame's header is not valid (its length is
  // checked before its bytes are awaited).
  std::optional<Message> read_any(Duration timeout);

  // Sends request (an "id" is added when it has none) and returns the reply: the first reply
  // line carrying that id, or carrying no id (the daemon could not read it). Lines in between
  // (scan events, replies to earlier requests) are kept for read_message, in order. Throws
  // SocketTimeout when no reply comes within timeout.
  nlohmann::json request(nlohmann::json request, Duration timeout);
  // request(), then throws ProtocolError with the daemon's code and message when it answered
  // "ok": false.
  nlohmann::json call(nlohmann::json request, Duration timeout);

  const std::string& path() const { return path_; }
  int native_handle() const { return fd_; }

 private:
  int fd_ = -1;
  std::string path_;
  std::string buffer_;               // bytes read, not yet returned as lines
  std::size_t scanned_ = 0;          // bytes of buffer_ known to hold no '\n'
  std::deque<Message> kept_;  // messages request() read past
  std::int64_t next_id_ = 1;

  // A line or a frame as it arrived: the bytes of a line without its '\n', or of a frame.
  struct Unit {
    std::string bytes;
    bool frame = false;
  };
  // The next whole unit in buffer_; nullopt when it is not complete yet.
  std::optional<Unit> take_unit();
  std::optional<Unit> read_unit(Duration timeout);
  Message parse(Unit unit) const;
  void close_fd();
};

// Throws ProtocolError when reply says "ok": false; returns reply otherwise.
const nlohmann::json& check_reply(const nlohmann::json& reply);

}  // namespace tofcomp::ipc::socket
