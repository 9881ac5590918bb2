#include "cli/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace tofcomp::cli {

Progress::Progress(std::string task, bool enabled)
    : task_(std::move(task)), enabled_(enabled), terminal_(::isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() {
  if (enabled_ && terminal_ && !finished_ && last_step_ >= 0) std::fputc('\n', stderr);
}

void Progress::update(double fraction, const std::string& detail) {
  if (!enabled_) return;
  const double clamped = std::clamp(fraction, 0.0, 1.0);
  const int percent = static_cast<int>(clamped * 100.0);
  if (terminal_) {
    if (percent == last_step_) return;
    std::fprintf(stderr, "\r%s: %3d%% %s\033[K", task_.c_str(), percent, detail.c_str());
    std::fflush(stderr);
    last_step_ = percent;
    return;
  }
  const int step = percent / 10;
  if (step == last_step_) return;
  last_step_ = step;
  std::fprintf(stderr, "%s: %d%% %s\n", task_.c_str(), step * 10, detail.c_str());
}

void Progress::done(const std::string& summary) {
  if (!enabled_ || finished_) return;
  finished_ = true;
  if (terminal_ && last_step_ >= 0) std::fputc('\n', stderr);
  std::fprintf(stderr, "%s: done%s%s\n", task_.c_str(), summary.empty() ? "" : ", ",
               summary.c_str());
}

}  // namespace tofcomp::cli
