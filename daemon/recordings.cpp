#include "daemon/recordings.hpp"

#include <spdlog/spdlog.h>

#include <utility>

#include "core/error.hpp"

namespace tofcomp::daemon {

Recordings::Recordings(RunFailed on_run_failed) : on_run_failed_(std::move(on_run_failed)) {}

void Recordings::configure(const settings::RecordingConfig& config) {
  recorder_.reset();
  if (config.enabled) {
    recorder_ = std::make_unique<Recorder>(
        RecorderSettings{config.directory, config.max_rows, config.max_minutes});
  }
}

Recorder& Recordings::start_run(RecorderSettings settings) {
  run_recorder_ = std::make_unique<Recorder>(std::move(settings));
  return *run_recorder_;
}

void Recordings::end_run() {
  run_recorder_.reset();
}

void Recordings::case_reading(double time_s, double case_c) {
  record([&](Recorder& r) { r.case_reading(time_s, case_c); });
}

void Recordings::power(double time_s, bool on) {
  record([&](Recorder& r) { r.power(time_s, on); });
}

void Recordings::scan(const realtime::RawScan& scan) {
  record([&](Recorder& r) { r.scan(scan); });
}

std::string Recordings::current_file() const {
  return recorder_ ? recorder_->current_file().string() : "off";
}

void Recordings::record(const std::function<void(Recorder&)>& write) {
  if (recorder_) {
    const bool was_suspended = recorder_->suspended();
    try {
      write(*recorder_);
    } catch (const core::Error& e) {
      // The recorder tries a new file after kRecorderRetryAfterS: one line per attempt.
      ++errors_;
      spdlog::error("recording suspended: {}; a new file is tried in {:g} s", e.what(),
                    kRecorderRetryAfterS);
    }
    if (was_suspended && !recorder_->suspended()) {
      spdlog::info("recording resumed in {}", recorder_->current_file().string());
    }
  }
  if (run_recorder_) {
    try {
      write(*run_recorder_);
    } catch (const core::Error& e) {
      ++errors_;
      run_recorder_.reset();
      on_run_failed_(e.what());
    }
  }
}

}  // namespace tofcomp::daemon
