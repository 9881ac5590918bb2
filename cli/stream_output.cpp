// Streaming output that ends cleanly on an interrupt or a closed pipe (cli/stream_output.hpp).
#include "cli/stream_output.hpp"

#include <signal.h>
#include <unistd.h>

#include <cstdio>

namespace tofcomp::cli {

namespace {

// The socket client retries poll(2) on EINTR, so a handler that only set a flag would be seen
// at the next scan at the earliest; the stream ends here instead. _exit is async-signal-safe,
// and the handler never runs inside a write (write_stream_line holds the signals), so every
// line printed is whole.
extern "C" void end_stream(int) { ::_exit(0); }

sigset_t interrupt_signals() {
  sigset_t set;
  ::sigemptyset(&set);
  ::sigaddset(&set, SIGINT);
  ::sigaddset(&set, SIGTERM);
  return set;
}

}  // namespace

void end_stream_on_interrupt() {
  struct sigaction action {};
  action.sa_handler = end_stream;
  ::sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
  // A closed pipe then shows as EPIPE from the write, which write_stream_line reports.
  ::signal(SIGPIPE, SIG_IGN);
}

bool write_stream_line(const std::string& text) {
  const sigset_t held = interrupt_signals();
  sigset_t before;
  ::sigprocmask(SIG_BLOCK, &held, &before);
  const bool written =
      std::fwrite(text.data(), 1, text.size(), stdout) == text.size() && std::fflush(stdout) == 0;
  ::sigprocmask(SIG_SETMASK, &before, nullptr);  // a signal that came meanwhile ends it here
  return written;
}

}  // namespace tofcomp::cli
