// The calibration run of §8.1: with a target at a known distance before the scanner, the daemon
// cycles the scanner's power (daemon/power_cycle_schedule.hpp) while it records the beams facing
// the target, each range with the known distance, the case readings and the power state, into
// the interchange CSV (daemon/recordings.hpp); when the schedule ends, the recalibration trains
// on that recording (daemon/recalibration.hpp). The scans are published throughout; while the
// scanner is off, the link's silence is expected and the host driver reconnects at once when
// the power comes back. Owns the power switch (made at the first run: `power.switch`, or the
// emulated scanner's supply), the schedule and the running run's configuration.
#pragma once

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "daemon/compensation_inputs.hpp"
#include "daemon/event_clock.hpp"
#include "daemon/power_cycle_schedule.hpp"
#include "daemon/recordings.hpp"
#include "daemon/scanner_link.hpp"
#include "daemon/service_status.hpp"
#include "hal/gpio/power_control.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

class PowerCycleRun {
 public:
  // Called on the loop once, when a started run ends (its recording closed): Finished, or
  // Failed with the reason.
  using Ended = std::function<void(PowerCycleSchedule::Phase phase, const std::string& why)>;

  struct Parts {
    ScannerLink& link;
    CompensationInputs& inputs;
    Recordings& recordings;
    ServiceStatus& service;
    const EventClock& clock;
  };

  PowerCycleRun(boost::asio::io_context& io, std::optional<hal::GpioLineConfig> power_switch,
                Parts parts, Ended on_ended);
  ~PowerCycleRun();  // cancels a running run
  PowerCycleRun(const PowerCycleRun&) = delete;
  PowerCycleRun& operator=(const PowerCycleRun&) = delete;

  // Makes the switch (at the first run), opens the run's recording with the pipeline's state and
  // sets the schedule up; empty, or why the run cannot start. Not while one runs.
  std::string prepare(const settings::PowerCycleRunConfig& run);
  // Starts the prepared run: the power goes on, cycle 1 begins.
  void start();
  // Stops a running run and switches the scanner back on.
  void cancel();
  // Drops the run (a running one is cancelled, the scanner switched back on).
  void drop() { schedule_.reset(); }
  // The run's recording failed (and was stopped): the run is cancelled and ends as failed.
  void recording_failed(const std::string& why);

  // What the prepared run does, for the recalibration's state.
  std::string describe() const;
  // Whether a run was prepared (and its progress is known).
  bool prepared() const { return schedule_ != nullptr; }
  bool running() const { return schedule_ && schedule_->running(); }
  PowerCycleSchedule::Progress progress() const { return schedule_->progress(); }
  const settings::PowerCycleRunConfig& config() const { return config_; }

 private:
  hal::PowerSwitch& power_switch();
  void on_switched(bool on);
  void on_schedule_ended(PowerCycleSchedule::Phase phase, const std::string& why);

  boost::asio::io_context& io_;
  std::optional<hal::GpioLineConfig> power_switch_config_;
  Parts parts_;
  Ended on_ended_;
  std::unique_ptr<hal::PowerSwitch> power_switch_;  // made at the first run
  std::unique_ptr<PowerCycleSchedule> schedule_;
  settings::PowerCycleRunConfig config_;  // the running one's (a reload may change the config)
};

}  // namespace tofcomp::daemon
