// tofcompd (or another program) run as a child process for the end-to-end tests: a
// configuration written to a temporary directory, the real binary started on it, its log kept,
// SIGHUP and SIGTERM sent.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/temporary_directory.hpp"

namespace tofcomp::test {

// A program run as a child process for the end-to-end tests, its stdout and stderr to a log.
class ChildProcess {
 public:
  // How long a child still running when the test ends gets to stop after SIGTERM.
  static constexpr std::chrono::seconds kStopLimit{10};
  ChildProcess(const char* program, const std::vector<std::string>& arguments,
               const std::filesystem::path& log)
      : log_(log) {
    std::vector<char*> argv{const_cast<char*>(program)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::execv(program, argv.data());
      ::_exit(127);
    }
  }
  // Stopped as a service manager stops it, so that it removes what it made (tofcompd its ring
  // in /dev/shm, which SIGKILL would leave behind); killed when it does not stop in time.
  ~ChildProcess() {
    if (pid_ > 0 && !exited_ && terminate(kStopLimit) < 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  void signal(int number) { ::kill(pid_, number); }

  // The exit status once it exits (128 + signal when a signal ended it), or -1 when it did not
  // exit within the limit.
  int wait_exit(std::chrono::seconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < until) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

  // The exit status after SIGTERM, or -1 when it did not exit within the limit.
  int terminate(std::chrono::seconds limit = std::chrono::seconds(20)) {
    ::kill(pid_, SIGTERM);
    return wait_exit(limit);
  }

  bool running() {
    int status = 0;
    return ::waitpid(pid_, &status, WNOHANG) == 0;
  }

  std::string log() const {
    std::ifstream in(log_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  std::filesystem::path log_;
};

// tofcompd (TOFCOMPD_BINARY, defined by the test's CMakeLists.txt) on a configuration file.
class DaemonProcess : public ChildProcess {
 public:
  DaemonProcess(const std::filesystem::path& config, const std::filesystem::path& log)
      : ChildProcess(TOFCOMPD_BINARY, {"--config", config.string()}, log) {}
};

// Waits until `path` exists; false after the limit.
inline bool wait_for_path(const std::filesystem::path& path, std::chrono::seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (std::filesystem::exists(path)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// Waits until a Unix socket at `path` accepts a connection. The daemon binds the socket (which
// makes the file) a moment before it listens, so a client that connects as soon as the file
// exists may be refused: waiting for the file alone made the end-to-end tests fail now and then.
inline bool wait_for_socket(const std::filesystem::path& path, std::chrono::seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string name = path.string();
  if (name.size() >= sizeof(address.sun_path)) return false;
  std::copy(name.begin(), name.end(), address.sun_path);
  while (std::chrono::steady_clock::now() < until) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return false;
    const bool accepted =
        ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0;
    ::close(fd);
    if (accepted) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace tofcomp::test
