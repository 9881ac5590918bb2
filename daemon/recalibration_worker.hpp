// Training in a thread of its own, so that the loop never blocks; the thread runs the training
// child (daemon/training_process.hpp: §3 thermal identification and §5 EM on one beam of a
// recording, calibration/training.hpp, the one way to train, under a time and a memory limit)
// and waits for it. The calibration the child made must then pass the gate
// (calibration/plausibility.hpp: its parameters in the LMS 200's physical scale, its held-out
// error no worse than the running calibration's by more than the margin) before it is written
// atomically; one that fails is not written, and the outcome says why. One job at a time; its
// outcome is taken on the loop. Owns the thread, the child and the outcome it leaves.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/calibration.hpp"
#include "daemon/training_process.hpp"
#include "io/checked_file.hpp"

namespace tofcomp::daemon {

class RecalibrationWorker {
 public:
  struct Job {
    io::CheckedFile recording;  // opened and checked by the caller
    int beam = 0;
    std::filesystem::path output;     // the calibration file to write
    std::filesystem::path datasheet;  // Algorithm 1's datasheet values
    // The calibration in use, for the held-out comparison; null when none.
    std::shared_ptr<const core::Calibration> running;
    TrainingLimits limits;
    bool model_search = true;  // the search of closing the loop runs on the part trained on
  };

  struct Outcome {
    std::string error;     // the training failed: why; empty otherwise
    std::string rejected;  // the gate refused the calibration: why; empty otherwise
    std::shared_ptr<const core::Calibration> calibration;  // when neither
    std::filesystem::path file;
    std::string note;  // what was trained on and held out
  };

  RecalibrationWorker() = default;
  ~RecalibrationWorker();  // stop()
  RecalibrationWorker(const RecalibrationWorker&) = delete;
  RecalibrationWorker& operator=(const RecalibrationWorker&) = delete;

  // Starts `job` in the thread; not while one runs.
  void start(Job job);
  // A job started and not yet taken.
  bool running() const { return running_; }
  // The training child's pid while it runs.
  std::optional<pid_t> child() const { return process_.child(); }
  // On the loop: the outcome of the job that ended (its thread joined), or nullopt.
  std::optional<Outcome> take();
  // Ends a running job at once (its training child is killed) and joins the thread; no job
  // starts after it.
  void stop();

 private:
  Outcome work(const Job& job);

  TrainingProcess process_;
  std::thread thread_;
  bool running_ = false;
  std::mutex outcome_mutex_;
  std::optional<Outcome> outcome_;  // set by the thread
};

}  // namespace tofcomp::daemon
