// One tofcompd per runtime directory (the socket's directory, /run/tofcompd under systemd): the
// daemon holds an exclusive flock on RUNTIME_DIR/tofcompd.lock for as long as it runs. The kernel
// drops the lock when the process ends, however it ends, so a daemon killed with SIGKILL never
// blocks the next start, and no pid is trusted (a pid is reused; a lock is not). The file holds
// the holder's pid for messages only.
#pragma once

#include <filesystem>
#include <string>

namespace tofcomp::daemon {

inline constexpr const char* kInstanceLockName = "tofcompd.lock";

class InstanceLock {
 public:
  // Creates the directory if needed, then takes the lock. Throws core::Error naming the file
  // when another process holds it ("another tofcompd (pid N) runs with ...") or it cannot be
  // taken.
  explicit InstanceLock(const std::filesystem::path& runtime_directory);
  ~InstanceLock();
  InstanceLock(const InstanceLock&) = delete;
  InstanceLock& operator=(const InstanceLock&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

}  // namespace tofcomp::daemon
