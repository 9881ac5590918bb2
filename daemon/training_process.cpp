// The training child from the daemon's side: see training_process.hpp.
#include "daemon/training_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <functional>
#include <vector>

#include "daemon/training_child.hpp"

extern char** environ;

namespace tofcomp::daemon {

namespace {

// The first descriptor after those the child finds (daemon/training_child.hpp).
constexpr int kFirstFreeFd = kRunningCalibrationFd + 1;
// A descriptor moved out of the way of the ones above before they are set up in the child.
constexpr int kHighFd = 10;
// How often the wait for the child's exit looks again once its output has ended.
constexpr int kExitPollMs = 10;

[[noreturn]] void fail(const std::string& what) {
  throw core::Error("training process: " + what + ": " + std::strerror(errno));
}

// A descriptor closed when it goes out of scope.
class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }
  int get() const { return fd_; }
  void reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }

 private:
  int fd_;
};

void make_pipe(Fd& read_end, Fd& write_end) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) fail("pipe2");
  read_end.reset(fds[0]);
  write_end.reset(fds[1]);
}

// A copy of fd at kHighFd or above, so that no dup2 in the child's set-up overwrites it first.
int high_copy(int fd) {
  const int copy = ::fcntl(fd, F_DUPFD_CLOEXEC, kHighFd);
  if (copy < 0) fail("fcntl(F_DUPFD_CLOEXEC)");
  return copy;
}

// The running calibration's text in an anonymous file the child reads from fd 3.
int memory_file(const std::string& text) {
  const int fd = ::memfd_create("tofcompd-running-calibration", MFD_CLOEXEC);
  if (fd < 0) fail("memfd_create");
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      ::close(fd);
      fail("write to the memory file");
    }
    done += static_cast<std::size_t>(n);
  }
  ::lseek(fd, 0, SEEK_SET);
  return fd;
}

std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::sigabbrev_np(sig);
    return "was killed by signal " + std::to_string(sig) +
           (name ? std::string(" (SIG") + name + ")" : "");
  }
  return "ended with wait status " + std::to_string(status);
}

// The last non-empty line of the child's messages: its error.
std::string last_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  const auto newline = text.rfind('\n');
  return newline == std::string::npos ? text : text.substr(newline + 1);
}

// Kills and reaps the child unless it was reaped; then forgets it.
struct Reaper {
  pid_t pid;
  std::function<void()> forget;
  bool reaped = false;
  int status = 0;
  Reaper(pid_t child, std::function<void()> then) : pid(child), forget(std::move(then)) {}
  Reaper(const Reaper&) = delete;
  Reaper& operator=(const Reaper&) = delete;
  ~Reaper() {
    if (!reaped) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
    }
    forget();
  }
};

}  // namespace

TrainingProcess::TrainingProcess() {
  if (::pipe2(cancel_pipe_, O_CLOEXEC | O_NONBLOCK) != 0) fail("pipe2 (cancel)");
}

TrainingProcess::~TrainingProcess() {
  ::close(cancel_pipe_[0]);
  ::close(cancel_pipe_[1]);
}

void TrainingProcess::cancel() {
  cancelled_ = true;
  const char byte = 1;
  [[maybe_unused]] const ssize_t ignored = ::write(cancel_pipe_[1], &byte, 1);
}

std::optional<pid_t> TrainingProcess::child() const {
  std::lock_guard lock(mutex_);
  return child_;
}

TrainingReport TrainingProcess::run(const TrainingRequest& request) {
  if (cancelled_) throw TrainingCancelled("training cancelled: the daemon is stopping");
  Fd out_read, out_write, err_read, err_write;
  make_pipe(out_read, out_write);
  make_pipe(err_read, err_write);
  Fd recording(high_copy(request.recording->fd()));
  Fd out_child(high_copy(out_write.get()));
  Fd err_child(high_copy(err_write.get()));
  Fd running;
  if (!request.running_calibration.empty()) {
    running.reset(memory_file(request.running_calibration));
    running.reset(high_copy(running.get()));
  }

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, recording.get(), STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out_child.get(), STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err_child.get(), STDERR_FILENO);
  if (running.get() >= 0) {
    posix_spawn_file_actions_adddup2(&actions, running.get(), kRunningCalibrationFd);
  }
  posix_spawn_file_actions_addclosefrom_np(&actions, kFirstFreeFd);
  // The child starts with default signal dispositions and nothing blocked.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigset_t none;
  sigemptyset(&none);
  sigfillset(&defaults);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

  const std::string program = request.program.string();
  std::vector<std::string> args = {program,          kTrainWorkerFlag,
                                   "--source",       request.source,
                                   "--beam",         std::to_string(request.beam),
                                   "--datasheet",    request.datasheet.string(),
                                   "--memory-bytes", std::to_string(request.limits.memory_bytes),
                                   "--time-s",       std::to_string(request.limits.time.count()),
                                   "--parent-pid",   std::to_string(::getpid())};
  if (running.get() >= 0) args.push_back("--running-calibration-on-fd-3");
  if (request.model_search) args.push_back("--model-search");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  pid_t pid = 0;
  const int spawned =
      ::posix_spawn(&pid, program.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (spawned != 0) {
    errno = spawned;
    fail("cannot start " + program + " " + kTrainWorkerFlag);
  }
  {
    std::lock_guard lock(mutex_);
    child_ = pid;
  }
  // The child has its own copies: the parent's write ends must go, or its output never ends.
  out_write.reset();
  err_write.reset();
  out_child.reset();
  err_child.reset();
  recording.reset();
  running.reset();

  // Whatever way run() ends, the child is gone after it.
  Reaper child{pid, [this] {
                 std::lock_guard lock(mutex_);
                 child_.reset();
               }};
  int& status = child.status;

  const auto deadline = std::chrono::steady_clock::now() + request.limits.time;
  std::string output, messages;
  bool out_open = true, err_open = true;
  std::array<char, 1 << 16> chunk{};
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      throw core::Error("training ran longer than " + std::to_string(request.limits.time.count()) +
                        " s (recalibration.limits.time_s) and was stopped");
    }
    std::array<pollfd, 3> fds{{{cancel_pipe_[0], POLLIN, 0},
                               {out_open ? out_read.get() : -1, POLLIN, 0},
                               {err_open ? err_read.get() : -1, POLLIN, 0}}};
    const bool outputs_ended = !out_open && !err_open;
    const int timeout =
        outputs_ended ? kExitPollMs : static_cast<int>(std::min<std::int64_t>(left.count(), 1000));
    const int ready = ::poll(fds.data(), fds.size(), timeout);
    if (ready < 0 && errno != EINTR) fail("poll");
    if (cancelled_) throw TrainingCancelled("training cancelled: the daemon is stopping");
    for (std::size_t i = 1; i < fds.size(); ++i) {
      if (fds[i].fd < 0 || (fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      const ssize_t n = ::read(fds[i].fd, chunk.data(), chunk.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        (i == 1 ? out_open : err_open) = false;
        continue;
      }
      std::string& into = i == 1 ? output : messages;
      const std::size_t cap = i == 1 ? kMaxTrainingOutputBytes : kMaxTrainingMessageBytes;
      if (into.size() + static_cast<std::size_t>(n) > cap) {
        throw core::Error("the training process wrote more than " + std::to_string(cap) +
                          " bytes to its " + (i == 1 ? "output" : "error stream") +
                          "; it was stopped");
      }
      into.append(chunk.data(), static_cast<std::size_t>(n));
    }
    if (outputs_ended) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        child.reaped = true;
        break;
      }
    }
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string why = last_line(messages);
    throw core::Error("the training process " + describe_status(status) +
                      (why.empty() ? std::string() : ": " + why));
  }
  TrainingReport report;
  try {
    report.summary = nlohmann::json::parse(output);
    report.calibration_yaml = report.summary.at("calibration").get<std::string>();
    report.summary.erase("calibration");
  } catch (const nlohmann::json::exception& e) {
    throw core::Error(std::string("the training process's output is not its report: ") + e.what());
  }
  return report;
}

}  // namespace tofcomp::daemon
