// The calibration run of §8.1: with a target at a known distance before the scanner, the daemon
// cycles the scanner's power (daemon/power_cycle_schedule.hpp) while it records the beams facing
// the target, each range with the known distance, the case readings and the power state, into
// the interchange CSV; then it trains on the recording in the worker thread and swaps the new
// calibration in between two scans, as for a recorded data set (daemon_control.cpp). The scans
// are published throughout; while the scanner is off, the link's silence is expected and the
// host driver reconnects at once when the power comes back.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "core/error.hpp"
#include "daemon/daemon.hpp"
#include "daemon/emulator_power_line.hpp"

namespace tofcomp::daemon {

using Clock = std::chrono::steady_clock;

// The GPIO switch of `power.switch`; without one, the emulated scanner's supply. Made once, at
// the first run, as on (the scanner runs while the daemon does).
hal::PowerSwitch& Daemon::power_switch() {
  if (!power_switch_) {
    if (config_.power.power_switch) {
      power_switch_ = std::make_unique<hal::PowerSwitch>(
          hal::make_power_switch(*config_.power.power_switch, true));
    } else if (emulator_) {
      power_switch_ = std::make_unique<hal::PowerSwitch>(
          std::make_unique<EmulatorPowerLine>(*emulator_), emulator_->power_on());
    } else {
      throw core::InvalidInput(
          "recalibration.source power_cycle_run needs power.switch: there is no scanner "
          "supply to switch");
    }
    spdlog::info("power switch: {}", power_switch_->describe());
  }
  return *power_switch_;
}

std::string Daemon::start_power_cycle_run() {
  const settings::PowerCycleRunConfig run = config_.recalibration.power_cycle_run;
  try {
    hal::PowerSwitch& power = power_switch();
    RecorderSettings settings;
    settings.directory = run.recording.parent_path();
    settings.file_name = run.recording.filename();
    settings.beams = std::pair{run.beams.first, run.beams.last};
    settings.true_range_mm = run.true_range_mm;
    run_recorder_ = std::make_unique<Recorder>(std::move(settings));
    // The run's data set starts from the state the pipeline is in.
    if (last_case_reading_) {
      run_recorder_->case_reading(last_case_reading_->first, last_case_reading_->second);
    }
    if (power_on_) run_recorder_->power(last_event_time_s_, *power_on_);
    run_config_ = run;
    run_ = std::make_unique<PowerCycleSchedule>(
        io_, power,
        PowerCycleSchedule::Settings{run.cycles, std::chrono::duration<double>(run.on_s),
                                     std::chrono::duration<double>(run.off_s)},
        [this](bool on) { on_run_switched(on); },
        [this](PowerCycleSchedule::Phase phase, const std::string& why) {
          on_run_ended(phase, why);
        });
  } catch (const core::Error& e) {
    run_recorder_.reset();
    run_.reset();
    return std::string("the power-cycle run cannot start: ") + e.what();
  }
  recalibration_state_ = "power-cycle run: " + std::to_string(run.cycles) + " cycles of " +
                         fmt::format("{:g} s on, {:g} s off", run.on_s, run.off_s) +
                         ", recording beams " + std::to_string(run.beams.first) + "-" +
                         std::to_string(run.beams.last) + " to " + run.recording.string();
  spdlog::info("recalibration: {}", recalibration_state_);
  run_->start();
  return {};
}

void Daemon::on_run_switched(bool on) {
  switched_off_ = !on;
  on_power(now_s(Clock::now()), on);
  if (on) {
    driver_->reconnect_now();
    set_status(ready_sent_ ? "publishing compensated scans" : "waiting for the first scan");
  } else {
    set_status("the scanner is switched off by the power-cycle run");
  }
}

void Daemon::on_run_ended(PowerCycleSchedule::Phase phase, const std::string& why) {
  run_recorder_.reset();  // flushed and closed
  if (phase != PowerCycleSchedule::Phase::Finished) {
    recalibration_state_ = "failed: power-cycle run: " + why;
    spdlog::error("recalibration {}", recalibration_state_);
    return;
  }
  spdlog::info("power-cycle run finished: training on {}", run_config_.recording.string());
  start_recalibration(run_config_.recording, run_config_.training_beam());
}

nlohmann::json Daemon::calibration_run_status() const {
  const PowerCycleSchedule::Progress p = run_->progress();
  std::string phase = to_string(p.phase);
  if (p.phase == PowerCycleSchedule::Phase::Cancelled &&
      recalibration_state_.rfind("failed", 0) == 0) {
    phase = "failed";  // cancelled by the daemon when the run's recording failed
  } else if (p.phase == PowerCycleSchedule::Phase::Finished) {
    phase = worker_running_                                ? "training"
            : recalibration_state_.rfind("done", 0) == 0   ? "done"
            : recalibration_state_.rfind("failed", 0) == 0 ? "failed"
                                                           : "finished";
  }
  nlohmann::json s = {{"phase", phase},
                      {"cycles", p.cycles},
                      {"recording", run_config_.recording.string()},
                      {"beams", {run_config_.beams.first, run_config_.beams.last}},
                      {"true_range_mm", run_config_.true_range_mm}};
  if (run_->running()) {
    s["cycle"] = p.cycle;
    s["time_left_s"] = std::round(p.time_left_s * 10.0) / 10.0;
  }
  return s;
}

}  // namespace tofcomp::daemon
