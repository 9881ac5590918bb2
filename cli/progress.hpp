// Progress of long work on stderr, so that stdout stays clean for results and --json.
// One line per 10 % step when stderr is not a terminal (logs), an updating line when it is.
#pragma once

#include <string>

namespace tofcomp::cli {

class Progress {
 public:
  Progress(std::string task, bool enabled);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // fraction in [0, 1]; detail is shown after the percentage (e.g. "iteration 12").
  void update(double fraction, const std::string& detail = {});
  void done(const std::string& summary = {});

 private:
  std::string task_;
  bool enabled_;
  bool terminal_;
  int last_step_ = -1;
  bool finished_ = false;
};

}  // namespace tofcomp::cli
