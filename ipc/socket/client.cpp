// The blocking client: a non-blocking socket driven with poll(2) and deadlines.
#include "ipc/socket/client.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>
#include <utility>

#include "ipc/socket/compact_frame.hpp"
#include "ipc/socket/protocol_error.hpp"

namespace tofcomp::ipc::socket {

namespace {

using Clock = std::chrono::steady_clock;

std::string errno_text(int error) {
  return std::strerror(error);
}

std::string hint(int error) {
  switch (error) {
    case ENOENT:
    case ECONNREFUSED:
      return "; is tofcompd running?";
    case EACCES:
    case EPERM:
      return "; does your user have access to the socket (its owner or group)?";
    default:
      return "";
  }
}

// Milliseconds left until deadline, for poll(2): 0 when past it.
int remaining_ms(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  return left.count() <= 0 ? 0 : static_cast<int>(std::min<std::int64_t>(left.count(), 1 << 30));
}

// Waits until fd is ready for events; false when deadline passed first.
bool wait_ready(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    pollfd p{fd, events, 0};
    const int n = ::poll(&p, 1, remaining_ms(deadline));
    if (n > 0) return true;
    if (n == 0) return false;
    if (errno != EINTR) throw core::Error(std::string("poll failed: ") + errno_text(errno));
  }
}

std::string describe(const nlohmann::json& request) {
  const auto op = request.find("op");
  return op != request.end() && op->is_string() ? "'" + op->get<std::string>() + "'"
                                                : "the request";
}

}  // namespace

SocketClient::SocketClient(const std::string& path, Duration timeout) : path_(path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof(address.sun_path)) {
    throw core::InvalidInput("socket path '" + path + "': must have 1 to " +
                             std::to_string(sizeof(address.sun_path) - 1) + " bytes");
  }
  std::memcpy(address.sun_path, path.data(), path.size());
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw core::Error("cannot create a Unix socket: " + errno_text(errno));
  // A listener whose queue is full answers EAGAIN; try again until the deadline.
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) return;
    const int error = errno;
    if (error == EINTR) continue;
    if (error == EAGAIN && Clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    close_fd();
    if (error == EAGAIN) {
      throw core::Error("cannot connect to " + path + ": its queue stayed full for " +
                        std::to_string(timeout.count()) + " ms; is tofcompd stuck?");
    }
    throw core::Error("cannot connect to " + path + ": " + errno_text(error) + hint(error));
  }
}

SocketClient::~SocketClient() {
  close_fd();
}

SocketClient::SocketClient(SocketClient&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      buffer_(std::move(other.buffer_)),
      scanned_(other.scanned_),
      kept_(std::move(other.kept_)),
      next_id_(other.next_id_) {}

SocketClient& SocketClient::operator=(SocketClient&& other) noexcept {
  if (this != &other) {
    close_fd();
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
    buffer_ = std::move(other.buffer_);
    scanned_ = other.scanned_;
    kept_ = std::move(other.kept_);
    next_id_ = other.next_id_;
  }
  return *this;
}

void SocketClient::close_fd() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void SocketClient::send_line(std::string_view line, Duration timeout) {
  if (line.find('\n') != std::string_view::npos) {
    throw core::InvalidInput("send_line: the line holds a '\\n'; one request is one line");
  }
  std::string framed(line);
  framed += '\n';
  send_bytes(framed, timeout);
}

void SocketClient::send_bytes(std::string_view bytes, Duration timeout) {
  if (fd_ < 0) throw SocketClosed("the connection to " + path_ + " is closed");
  const auto deadline = Clock::now() + timeout;
  while (!bytes.empty()) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n >= 0) {
      bytes.remove_prefix(static_cast<std::size_t>(n));
      continue;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN) {
      if (!wait_ready(fd_, POLLOUT, deadline)) {
        throw SocketTimeout("tofcompd at " + path_ + " took no bytes for " +
                          std::to_string(timeout.count()) + " ms");
      }
      continue;
    }
    if (errno == EPIPE || errno == ECONNRESET) {
      throw SocketClosed("tofcompd at " + path_ + " closed the connection");
    }
    throw core::Error("cannot write to " + path_ + ": " + errno_text(errno));
  }
}

std::optional<SocketClient::Unit> SocketClient::take_unit() {
  if (!buffer_.empty() && static_cast<unsigned char>(buffer_[0]) == kCompactMagic[0]) {
    if (buffer_.size() < kCompactHeaderBytes) return std::nullopt;
    std::size_t size = 0;
    try {
      size = compact_frame_size(std::string_view(buffer_).substr(0, kCompactHeaderBytes));
    } catch (const core::InvalidInput& e) {
      throw core::Error("tofcompd at " + path_ + " sent a bad " + e.what());
    }
    if (buffer_.size() < size) return std::nullopt;
    Unit unit{buffer_.substr(0, size), true};
    buffer_.erase(0, size);
    scanned_ = 0;
    return unit;
  }
  const auto newline = buffer_.find('\n', scanned_);
  if (newline == std::string::npos) {
    scanned_ = buffer_.size();
    return std::nullopt;
  }
  Unit unit{buffer_.substr(0, newline), false};
  buffer_.erase(0, newline + 1);
  scanned_ = 0;
  return unit;
}

std::optional<SocketClient::Unit> SocketClient::read_unit(Duration timeout) {
  if (auto unit = take_unit()) return unit;
  if (fd_ < 0) throw SocketClosed("the connection to " + path_ + " is closed");
  const auto deadline = Clock::now() + timeout;
  char chunk[65536];
  for (;;) {
    const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
    if (n > 0) {
      buffer_.append(chunk, static_cast<std::size_t>(n));
      if (auto unit = take_unit()) return unit;
      if (buffer_.size() > kClientMaxLineBytes) {
        throw core::Error("tofcompd at " + path_ + " sent a line longer than " +
                          std::to_string(kClientMaxLineBytes) + " bytes");
      }
      continue;
    }
    if (n == 0) {
      throw SocketClosed("tofcompd at " + path_ + " closed the connection" +
                         (buffer_.empty() ? "" : " in the middle of a line"));
    }
    if (errno == EINTR) continue;
    if (errno == ECONNRESET) {
      throw SocketClosed("tofcompd at " + path_ + " reset the connection");
    }
    if (errno != EAGAIN) throw core::Error("cannot read from " + path_ + ": " + errno_text(errno));
    if (!wait_ready(fd_, POLLIN, deadline)) return std::nullopt;
  }
}

Message SocketClient::parse(Unit unit) const {
  if (unit.frame) return Message{nullptr, std::move(unit.bytes)};
  try {
    return Message{nlohmann::json::parse(unit.bytes), {}};
  } catch (const nlohmann::json::exception& e) {
    throw core::Error("tofcompd at " + path_ + " sent a line that is not JSON: " + e.what());
  }
}

std::optional<std::string> SocketClient::read_line(Duration timeout) {
  auto unit = read_unit(timeout);
  if (!unit) return std::nullopt;
  if (unit->frame) {
    throw core::Error("tofcompd at " + path_ + " sent a compact frame where a line was expected");
  }
  return std::move(unit->bytes);
}

std::optional<Message> SocketClient::read_any(Duration timeout) {
  if (!kept_.empty()) {
    Message message = std::move(kept_.front());
    kept_.pop_front();
    return message;
  }
  auto unit = read_unit(timeout);
  if (!unit) return std::nullopt;
  return parse(std::move(*unit));
}

std::optional<nlohmann::json> SocketClient::read_message(Duration timeout) {
  auto message = read_any(timeout);
  if (!message) return std::nullopt;
  if (message->is_frame()) {
    throw core::Error("tofcompd at " + path_ +
                      " sent a compact frame where a JSON line was expected");
  }
  return std::move(message->json);
}

nlohmann::json SocketClient::request(nlohmann::json request, Duration timeout) {
  if (!request.is_object()) throw core::InvalidInput("request: must be a JSON object");
  if (!request.contains("id")) request["id"] = next_id_++;
  const nlohmann::json id = request["id"];
  send_line(request.dump(), timeout);
  const auto deadline = Clock::now() + timeout;
  std::deque<Message> passed;
  for (;;) {
    const auto left = std::chrono::duration_cast<Duration>(deadline - Clock::now());
    // Messages kept earlier are not this request's reply: read from the socket.
    auto unit = read_unit(std::max(left, Duration(0)));
    if (!unit) {
      for (auto& m : passed) kept_.push_back(std::move(m));
      throw SocketTimeout("no reply to " + describe(request) + " from tofcompd at " + path_ +
                        " within " + std::to_string(timeout.count()) + " ms");
    }
    Message message = parse(std::move(*unit));
    const nlohmann::json& json = message.json;
    const bool is_reply = json.is_object() && json.contains("ok");
    const auto reply_id = is_reply ? json.find("id") : json.end();
    if (is_reply && (reply_id == json.end() || *reply_id == id)) {
      for (auto& m : passed) kept_.push_back(std::move(m));
      return std::move(message.json);
    }
    passed.push_back(std::move(message));
  }
}

nlohmann::json SocketClient::call(nlohmann::json request, Duration timeout) {
  nlohmann::json reply = this->request(std::move(request), timeout);
  check_reply(reply);
  return reply;
}

const nlohmann::json& check_reply(const nlohmann::json& reply) {
  if (reply.value("ok", false)) return reply;
  const auto error = reply.find("error");
  if (error == reply.end() || !error->is_object()) {
    throw core::Error("tofcompd answered without ok:true and without an error: " +
                      reply.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  }
  const std::string name = error->value("code", "");
  const auto code = error_code_from_string(name);
  const std::string message = error->value("message", "");
  std::optional<nlohmann::json> id;
  if (const auto it = reply.find("id"); it != reply.end()) id = *it;
  if (!code) {
    throw core::Error("tofcompd answered with the unknown error code '" + name + "': " + message);
  }
  throw ProtocolError(*code, message, id);
}

}  // namespace tofcomp::ipc::socket
