// One tofcompd per socket: the daemon holds an exclusive flock on the lock file beside its socket
// (the socket's name with .lock for its extension: /run/tofcompd/tofcompd.lock for
// /run/tofcompd/tofcompd.sock) for as long as it runs. Instances with sockets of their own in one
// directory each hold their own. The kernel
// drops the lock when the process ends, however it ends, so a daemon killed with SIGKILL never
// blocks the next start, and no pid is trusted (a pid is reused; a lock is not). The file holds
// the holder's pid for messages only.
#pragma once

#include <filesystem>
#include <string>

namespace tofcomp::daemon {

inline constexpr const char* kInstanceLockExtension = ".lock";

class InstanceLock {
 public:
  // Creates the socket's directory if needed, then takes the lock. Throws core::Error naming the
  // file when another process holds it ("another tofcompd (pid N) runs with the socket ...") or
  // it cannot be taken.
  explicit InstanceLock(const std::filesystem::path& socket_path);
  ~InstanceLock();
  InstanceLock(const InstanceLock&) = delete;
  InstanceLock& operator=(const InstanceLock&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

}  // namespace tofcomp::daemon
