// take_activated_socket over libsystemd's sd_listen_fds and sd_is_socket_unix.
#include "daemon/service/socket_activation.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <systemd/sd-daemon.h>

#include <cstddef>
#include <cstring>

#include "core/error.hpp"

namespace tofcomp::daemon::service {
namespace {

// tofcompd serves one socket: its protocol's (docs/protocol.md).
constexpr int kSocketsServed = 1;

// The path a Unix socket is bound to; empty for an unnamed or abstract one.
std::string bound_path(int fd) {
  sockaddr_un address{};
  socklen_t length = sizeof(address);
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) return {};
  const auto path_bytes = static_cast<std::size_t>(length) - offsetof(sockaddr_un, sun_path);
  if (length <= offsetof(sockaddr_un, sun_path) || address.sun_path[0] == '\0') return {};
  return std::string(address.sun_path, ::strnlen(address.sun_path, path_bytes));
}

}  // namespace

std::optional<ActivatedSocket> take_activated_socket() {
  // 1: unset LISTEN_PID, LISTEN_FDS and LISTEN_FDNAMES (sd_listen_fds(3)); the descriptors get
  // FD_CLOEXEC.
  const int passed = ::sd_listen_fds(1);
  if (passed < 0) {
    throw core::Error("cannot read the sockets the service manager passed (LISTEN_FDS): " +
                      std::string(std::strerror(-passed)));
  }
  if (passed == 0) return std::nullopt;
  if (passed != kSocketsServed) {
    throw core::Error("the service manager passed " + std::to_string(passed) +
                      " sockets (LISTEN_FDS); tofcompd serves one: a Unix stream socket "
                      "(ListenStream=PATH in tofcompd.socket)");
  }
  const int fd = SD_LISTEN_FDS_START;
  const int is_unix_stream_listening = ::sd_is_socket_unix(fd, SOCK_STREAM, 1, nullptr, 0);
  if (is_unix_stream_listening <= 0) {
    throw core::Error(
        "the socket the service manager passed (fd " + std::to_string(fd) +
        ") is not a listening Unix stream socket; tofcompd serves one (ListenStream=PATH in "
        "tofcompd.socket, not ListenDatagram=, not a TCP port)");
  }
  ActivatedSocket socket{fd, bound_path(fd)};
  if (socket.path.empty()) {
    throw core::Error("the socket the service manager passed (fd " + std::to_string(fd) +
                      ") has no path in the file system, where tofcompd's clients look for it");
  }
  return socket;
}

}  // namespace tofcomp::daemon::service
