// A shared-memory ring planted under a name by another user: a child process that drops to
// nobody, makes a complete ring there with one fake scan in it and holds it (and its writer's
// lock) until the PlantedRing is destroyed, which lets the child go and reaps it. For the tests
// of a ring or a daemon that must leave another user's object alone. Needs root.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "ipc/compensated_scan.hpp"
#include "ipc/ring/ring_writer.hpp"

namespace tofcomp::test {

class PlantedRing {
 public:
  static constexpr uid_t kNobody = 65534;  // Debian's nobody: neither root nor the test's user
  static constexpr std::uint64_t kFakeSequence = 666;  // the planted scan's sequence number

  explicit PlantedRing(const std::string& name) {
    int ready[2];
    int release[2];
    if (::pipe(ready) != 0 || ::pipe(release) != 0) throw std::runtime_error("pipe failed");
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) plant(name, ready[1], release[0]);
    ::close(ready[1]);
    ::close(release[0]);
    release_fd_ = release[1];
    char byte = 0;
    const bool planted = ::read(ready[0], &byte, 1) == 1;
    ::close(ready[0]);
    if (!planted) {
      let_go();
      throw std::runtime_error("the planter could not make a ring under " + name);
    }
  }
  ~PlantedRing() { let_go(); }
  PlantedRing(const PlantedRing&) = delete;
  PlantedRing& operator=(const PlantedRing&) = delete;

 private:
  // In the child: as nobody, the ring with its fake scan; then wait to be let go.
  [[noreturn]] static void plant(const std::string& name, int ready, int release) {
    int code = 0;
    if (::setgid(kNobody) != 0 || ::setuid(kNobody) != 0) ::_exit(100);
    try {
      ipc::ring::RingWriter fake(name, 4, 4, ipc::ring::RingWriterOptions{0644, true, false});
      ipc::CompensatedScan scan;
      scan.sequence = kFakeSequence;
      scan.beams.resize(4);
      fake.publish(scan);
      char byte = 'r';
      if (::write(ready, &byte, 1) != 1) code = 2;
      if (::read(release, &byte, 1) != 1) code = 3;
    } catch (...) {
      code = 1;
    }
    ::_exit(code);
  }

  void let_go() {
    if (pid_ <= 0) return;
    const char go = 'g';
    [[maybe_unused]] const ssize_t n = ::write(release_fd_, &go, 1);
    ::close(release_fd_);
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

  pid_t pid_ = -1;
  int release_fd_ = -1;
};

}  // namespace tofcomp::test
