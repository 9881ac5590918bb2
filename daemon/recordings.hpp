// The recordings of what the pipeline takes in (daemon/recorder.hpp): the configured one
// (`recording`), and a calibration run's recording while the run records (§8.1,
// daemon/power_cycle_run.hpp). Owns both recorders and the count of recording errors. Each row
// goes to every recorder running. The configured one that fails (a full disk) is suspended and
// tries a new file after a while (daemon/recorder.hpp), each failure and the resumption logged;
// a run's recording that fails is stopped and reported to the run.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "daemon/recorder.hpp"
#include "realtime/raw_scan.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

class Recordings {
 public:
  // Called on the loop when the run's recording failed (it is stopped by then), with why.
  using RunFailed = std::function<void(const std::string& why)>;

  explicit Recordings(RunFailed on_run_failed);

  // Stops the configured recording, and starts it anew when `config` enables it. Throws
  // core::Error when its directory cannot be made.
  void configure(const settings::RecordingConfig& config);
  // Opens a calibration run's recording (throws core::Error when it cannot), which the caller
  // starts with the pipeline's state.
  Recorder& start_run(RecorderSettings settings);
  // Flushes and closes the run's recording.
  void end_run();

  void case_reading(double time_s, double case_c);
  void power(double time_s, bool on);
  void scan(const realtime::RawScan& scan);

  // The configured recording's file, or "off".
  std::string current_file() const;
  // The configured recording; null when it is off.
  const Recorder* configured() const { return recorder_.get(); }
  std::uint64_t errors() const { return errors_; }

 private:
  void record(const std::function<void(Recorder&)>& write);

  RunFailed on_run_failed_;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<Recorder> run_recorder_;
  std::uint64_t errors_ = 0;
};

}  // namespace tofcomp::daemon
