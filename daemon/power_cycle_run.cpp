#include "daemon/power_cycle_run.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::daemon {

namespace {
constexpr const char* kSwitchedOffStatus = "the scanner is switched off by the power-cycle run";
}  // namespace

PowerCycleRun::PowerCycleRun(boost::asio::io_context& io,
                             std::optional<hal::GpioLineConfig> power_switch, Parts parts,
                             Ended on_ended)
    : io_(io),
      power_switch_config_(std::move(power_switch)),
      parts_(parts),
      on_ended_(std::move(on_ended)) {}

PowerCycleRun::~PowerCycleRun() = default;

// The GPIO switch of `power.switch`; without one, the emulated scanner's supply. Made once, at
// the first run, as on (the scanner runs while the daemon does).
hal::PowerSwitch& PowerCycleRun::power_switch() {
  if (!power_switch_) {
    if (power_switch_config_) {
      power_switch_ =
          std::make_unique<hal::PowerSwitch>(hal::make_power_switch(*power_switch_config_, true));
    } else {
      power_switch_ = parts_.link.supply_switch();
      if (!power_switch_) {
        throw core::InvalidInput(
            "recalibration.source power_cycle_run needs power.switch: there is no scanner "
            "supply to switch");
      }
    }
    spdlog::info("power switch: {}", power_switch_->describe());
  }
  return *power_switch_;
}

std::string PowerCycleRun::prepare(const settings::PowerCycleRunConfig& run) {
  try {
    hal::PowerSwitch& power = power_switch();
    RecorderSettings settings;
    settings.directory = run.recording.parent_path();
    settings.file_name = run.recording.filename();
    settings.beams = std::pair{run.beams.first, run.beams.last};
    settings.true_range_mm = run.true_range_mm;
    // The run's recording starts from the state the pipeline is in.
    parts_.inputs.seed(parts_.recordings.start_run(std::move(settings)));
    config_ = run;
    schedule_ = std::make_unique<PowerCycleSchedule>(
        io_, power,
        PowerCycleSchedule::Settings{run.cycles, std::chrono::duration<double>(run.on_s),
                                     std::chrono::duration<double>(run.off_s)},
        [this](bool on) { on_switched(on); },
        [this](PowerCycleSchedule::Phase phase, const std::string& why) {
          on_schedule_ended(phase, why);
        });
  } catch (const core::Error& e) {
    parts_.recordings.end_run();
    schedule_.reset();
    return std::string("the power-cycle run cannot start: ") + e.what();
  }
  return {};
}

void PowerCycleRun::start() {
  schedule_->start();
}

void PowerCycleRun::cancel() {
  if (schedule_) schedule_->cancel();
}

void PowerCycleRun::recording_failed(const std::string& why) {
  cancel();
  on_schedule_ended(PowerCycleSchedule::Phase::Failed, "the run's recording failed: " + why);
}

std::string PowerCycleRun::describe() const {
  return std::to_string(config_.cycles) + " cycles of " +
         fmt::format("{:g} s on, {:g} s off", config_.on_s, config_.off_s) + ", recording beams " +
         std::to_string(config_.beams.first) + "-" + std::to_string(config_.beams.last) + " to " +
         config_.recording.string();
}

void PowerCycleRun::on_switched(bool on) {
  parts_.inputs.switched(parts_.clock.now_s(), on);
  if (on) {
    parts_.link.reconnect_now();
    parts_.service.show_scan_state();
  } else {
    parts_.service.set(kSwitchedOffStatus);
  }
}

void PowerCycleRun::on_schedule_ended(PowerCycleSchedule::Phase phase, const std::string& why) {
  parts_.recordings.end_run();  // flushed and closed
  on_ended_(phase, why);
}

}  // namespace tofcomp::daemon
