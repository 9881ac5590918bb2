// Running another program and waiting for it, without a shell: the arguments are passed as
// they are (no quoting), the program is looked up on PATH when it has no '/'.
#pragma once

#include <string>
#include <vector>

namespace tofcomp::cli {

struct ChildOutcome {
  bool started = false;  // false: the program could not be run at all (e.g. not found)
  int exit_code = -1;    // the child's exit status; 128 + signal when a signal ended it
  std::string output;    // its stdout, when captured
};

enum class ChildStdout {
  Capture,   // into ChildOutcome::output
  ToStderr,  // so that the parent's stdout stays clean for results and --json
};

// Runs argv[0] with argv; stderr is inherited. Throws core::Error only when the system cannot
// make a pipe or wait for the child; a program that cannot be found is started = false.
ChildOutcome run_child(const std::vector<std::string>& argv, ChildStdout stdout_mode);

}  // namespace tofcomp::cli
