// Recalibration (docs/daemon.md, "Recalibration"): on a recording (measured data with a known
// distance), or on the recording of a power-cycle run (daemon/power_cycle_run.hpp), trained in
// the worker (daemon/recalibration_worker.hpp: a process of its own, under limits, then the
// plausibility gate) and swapped into the pipeline on the loop, between two scans. Asked for by a
// client, or at start when the calibration is missing. A client names a recording only in
// recalibration.recording.directory, and only a regular file no larger than the limit is opened
// (io/checked_file.hpp); the checks are made before the reply, which says what is wrong. Owns the
// worker, the run and the recalibration's state.
#pragma once

#include <boost/asio/io_context.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "daemon/compensation_inputs.hpp"
#include "daemon/power_cycle_run.hpp"
#include "daemon/recalibration_worker.hpp"
#include "daemon/running_config.hpp"
#include "daemon/socket/request_handler.hpp"

namespace tofcomp::daemon {

class Recalibration {
 public:
  Recalibration(boost::asio::io_context& io, const RunningConfig& config,
                PowerCycleRun::Parts parts);
  ~Recalibration();  // stop()
  Recalibration(const Recalibration&) = delete;
  Recalibration& operator=(const Recalibration&) = delete;

  // At start: recalibrates when there is no calibration and the trigger is at_start_if_missing.
  void start_if_missing();
  // A client's request; args: {} or {"recording": path}. Throws core::InvalidInput for bad args.
  socket::RecalibrationResult request(const nlohmann::json& args);
  // On the loop's housekeeping: swaps in the calibration a finished training made.
  void finish();
  // At shutdown: a calibration run cut short leaves the scanner powered.
  void cancel_run();
  // Waits for a training that runs, then drops the run (a running one is cancelled).
  void stop();
  // The run's recording failed.
  void run_recording_failed(const std::string& why);

  const std::string& state() const { return state_; }
  // The training process's pid while one runs.
  std::optional<pid_t> training_pid() const { return worker_.child(); }
  // The calibration run's progress (status.calibration_run); null when none was prepared.
  nlohmann::json run_status() const;

 private:
  // Opens and checks the configured recording `data` (not a client's): core::InvalidInput if it
  // is refused.
  io::CheckedFile open_configured(const std::filesystem::path& data) const;
  // A client's recording: only in the recordings directory.
  io::CheckedFile open_from_client(const std::filesystem::path& named) const;
  void start_training(io::CheckedFile data, int beam);
  std::string start_power_cycle_run();  // empty, or why it cannot start
  void on_run_ended(PowerCycleSchedule::Phase phase, const std::string& why);

  const RunningConfig& config_;
  CompensationInputs& inputs_;
  std::string state_ = "idle";
  PowerCycleRun run_;
  RecalibrationWorker worker_;  // joined before the run is dropped
};

}  // namespace tofcomp::daemon
