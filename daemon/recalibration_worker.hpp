// Training in a thread of its own, so that the loop never blocks: §3 thermal identification and
// §5 EM on one beam of a recording (calibration/training.hpp, the one way to train), the
// calibration written atomically. One job at a time; its outcome is taken on the loop. Owns the
// thread and the outcome it leaves.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/calibration.hpp"

namespace tofcomp::daemon {

class RecalibrationWorker {
 public:
  struct Job {
    std::filesystem::path data;  // the recording to train on
    int beam = 0;
    std::filesystem::path output;     // the calibration file to write
    std::filesystem::path datasheet;  // Algorithm 1's datasheet values
  };

  struct Outcome {
    std::string error;  // empty on success
    std::shared_ptr<const core::Calibration> calibration;
    std::filesystem::path file;
  };

  RecalibrationWorker() = default;
  ~RecalibrationWorker();  // join()
  RecalibrationWorker(const RecalibrationWorker&) = delete;
  RecalibrationWorker& operator=(const RecalibrationWorker&) = delete;

  // Starts `job` in the thread; not while one runs.
  void start(Job job);
  // A job started and not yet taken.
  bool running() const { return running_; }
  // On the loop: the outcome of the job that ended (its thread joined), or nullopt.
  std::optional<Outcome> take();
  // Waits for a job that runs.
  void join();

 private:
  std::thread thread_;
  bool running_ = false;
  std::mutex outcome_mutex_;
  std::optional<Outcome> outcome_;  // set by the thread
};

}  // namespace tofcomp::daemon
