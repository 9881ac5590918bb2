// The runtime directory's lock: see instance_lock.hpp.
#include "daemon/instance_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "core/error.hpp"

namespace tofcomp::daemon {

namespace {

constexpr mode_t kLockFileMode = 0644;
constexpr std::size_t kPidTextBytes = 32;

// The socket's path with the lock's extension; a socket whose name already ends so gets it added.
std::filesystem::path lock_path(const std::filesystem::path& socket_path) {
  std::filesystem::path lock = socket_path;
  lock.replace_extension(kInstanceLockExtension);
  if (lock == socket_path) lock += kInstanceLockExtension;
  return lock;
}

}  // namespace

InstanceLock::InstanceLock(const std::filesystem::path& socket_path)
    : path_(lock_path(socket_path)) {
  std::error_code ignored;  // a failure shows when the file cannot be opened, naming it
  std::filesystem::create_directories(path_.parent_path(), ignored);
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, kLockFileMode);
  if (fd_ < 0) {
    throw core::Error("cannot open the lock file " + path_.string() + ": " + std::strerror(errno));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    char text[kPidTextBytes] = {};
    const ssize_t n = ::pread(fd_, text, sizeof text - 1, 0);
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      const std::string holder = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : "";
      throw core::Error("another tofcompd" +
                        (holder.empty() ? std::string() : " (pid " + holder + ")") +
                        " runs with the socket " + socket_path.string() +
                        ": it holds " + path_.string() + "; not starting a second");
    }
    throw core::Error("cannot lock " + path_.string() + ": " + std::strerror(error));
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
  }
}

InstanceLock::~InstanceLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock; the file stays for the next start
}

}  // namespace tofcomp::daemon
