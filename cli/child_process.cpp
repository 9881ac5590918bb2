#include "cli/child_process.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.hpp"

extern char** environ;

namespace tofcomp::cli {
namespace {

std::string system_error(const std::string& what) {
  return what + ": " + std::strerror(errno);
}

// The child's stdout read to its end, then the pipe closed.
std::string drain(int fd) {
  std::string out;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n > 0) {
      out.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fd);
  return out;
}

}  // namespace

ChildOutcome run_child(const std::vector<std::string>& argv, ChildStdout stdout_mode) {
  if (argv.empty()) throw core::InvalidInput("run_child needs a program to run");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  int pipe_fds[2] = {-1, -1};
  if (stdout_mode == ChildStdout::Capture && ::pipe(pipe_fds) != 0) {
    throw core::Error(system_error("cannot make a pipe to run " + argv[0]));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (stdout_mode == ChildStdout::Capture) {
    posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
  } else {
    posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  }
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);

  ChildOutcome outcome;
  if (stdout_mode == ChildStdout::Capture) {
    ::close(pipe_fds[1]);
    if (spawned == 0) {
      outcome.output = drain(pipe_fds[0]);
    } else {
      ::close(pipe_fds[0]);
    }
  }
  if (spawned != 0) return outcome;

  outcome.started = true;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw core::Error(system_error("cannot wait for " + argv[0]));
  }
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return outcome;
}

}  // namespace tofcomp::cli
