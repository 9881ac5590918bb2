// Socket file checks with plain POSIX calls (lstat, a non-blocking connect, unlink).
#include "daemon/socket/socket_path.hpp"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.hpp"

namespace tofcomp::daemon::socket {

bool someone_listens(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof(address.sun_path)) {
    throw core::InvalidInput("socket path '" + path + "': longer than " +
                             std::to_string(sizeof(address.sun_path) - 1) + " bytes");
  }
  std::memcpy(address.sun_path, path.data(), path.size());
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0)
    throw core::Error(std::string("cannot create a Unix socket: ") + std::strerror(errno));
  int result = 0;
  do {
    result = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  } while (result != 0 && errno == EINTR);
  const int error = result == 0 ? 0 : errno;
  ::close(fd);
  if (result == 0 || error == EAGAIN) return true;
  if (error == ECONNREFUSED || error == ENOENT) return false;
  throw core::Error("cannot tell whether a daemon listens on " + path + ": " +
                    std::strerror(error));
}

bool clear_stale_socket(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return false;
    throw core::Error("cannot check the socket path " + path + ": " + std::strerror(errno));
  }
  if (!S_ISSOCK(st.st_mode)) {
    throw core::Error("the socket path " + path +
                      " exists and is not a socket; remove it or choose another path");
  }
  if (someone_listens(path)) {
    throw core::Error("another tofcompd is listening on " + path + "; not starting a second");
  }
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
    throw core::Error("cannot remove the stale socket " + path + ": " + std::strerror(errno));
  }
  return true;
}

std::optional<FileIdentity> identity_of(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return std::nullopt;
  return FileIdentity{st.st_dev, st.st_ino};
}

void remove_if_same(const std::string& path, const FileIdentity& made) {
  if (identity_of(path) == made) ::unlink(path.c_str());
}

}  // namespace tofcomp::daemon::socket
