// Training in a process of its own (docs/daemon.md, "Recalibration"): tofcompd runs itself as
// `tofcompd --train-worker` (daemon/training_child.hpp) on a recording it has opened and checked,
// under a memory limit (RLIMIT_AS) and a time limit, and reads back the calibration and the
// held-out scores. Whatever the data do to training — run for hours, take all memory, crash — the
// daemon goes on, and cancel() (at SIGTERM) ends the child at once: the daemon never waits for a
// training to finish. The calling thread blocks in run(); cancel() may come from any thread.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "io/checked_file.hpp"

namespace tofcomp::daemon {

// Where the training child's output stops being believable: a calibration file is kilobytes.
inline constexpr std::size_t kMaxTrainingOutputBytes = 16u << 20;
inline constexpr std::size_t kMaxTrainingMessageBytes = 64u << 10;

struct TrainingLimits {
  std::chrono::seconds time{0};
  std::uint64_t memory_bytes = 0;
};

struct TrainingRequest {
  const io::CheckedFile* recording = nullptr;  // read as the child's standard input
  std::string source;                          // the recording's name, for messages
  int beam = 0;
  std::filesystem::path datasheet;
  // The running calibration's file text, for the held-out comparison; empty when none.
  std::string running_calibration;
  TrainingLimits limits;
  bool model_search = true;  // closing the loop: the model search on the part trained on
  std::filesystem::path program = "/proc/self/exe";  // tofcompd itself
};

// What the child printed: the calibration's file text and what it says of its training.
struct TrainingReport {
  std::string calibration_yaml;
  nlohmann::json summary;
};

class TrainingCancelled : public core::Error {
 public:
  using core::Error::Error;
};

class TrainingProcess {
 public:
  TrainingProcess();
  ~TrainingProcess();
  TrainingProcess(const TrainingProcess&) = delete;
  TrainingProcess& operator=(const TrainingProcess&) = delete;

  // Runs a training child to its end. Throws TrainingCancelled after cancel(), core::Error with
  // the reason when the child fails, runs past its time, or cannot be started. One at a time.
  TrainingReport run(const TrainingRequest& request);
  // Kills the running child (if any) and makes run() return; every later run() is cancelled at
  // once too (the daemon is stopping).
  void cancel();
  // The child's pid while one runs.
  std::optional<pid_t> child() const;

 private:
  int cancel_pipe_[2] = {-1, -1};
  std::atomic<bool> cancelled_{false};
  mutable std::mutex mutex_;
  std::optional<pid_t> child_;
};

}  // namespace tofcomp::daemon
