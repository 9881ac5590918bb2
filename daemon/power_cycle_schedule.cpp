#include "daemon/power_cycle_schedule.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"
#include "hal/gpio/gpio_line.hpp"

namespace tofcomp::daemon {

using Clock = std::chrono::steady_clock;

PowerCycleSchedule::PowerCycleSchedule(boost::asio::io_context& io, hal::PowerSwitch& power,
                                       Settings settings, Switched on_switched, Ended on_ended)
    : timer_(io),
      power_(power),
      settings_(settings),
      on_switched_(std::move(on_switched)),
      on_ended_(std::move(on_ended)) {
  if (settings_.cycles < 1) {
    throw core::InvalidInput("power-cycle run: at least one cycle, not " +
                             std::to_string(settings_.cycles));
  }
  if (!(settings_.on.count() > 0.0) || !(settings_.off.count() > 0.0)) {
    throw core::InvalidInput("power-cycle run: the on and off durations must be positive");
  }
}

PowerCycleSchedule::~PowerCycleSchedule() {
  on_switched_ = nullptr;  // the owner may be half destroyed: it hears nothing more
  cancel();
}

bool PowerCycleSchedule::set_power(bool on) {
  try {
    power_.set(on);
  } catch (const hal::GpioError& e) {
    phase_ = Phase::Failed;
    timer_.cancel();
    if (on_ended_)
      on_ended_(phase_,
                std::string("switching the power ") + (on ? "on" : "off") + " failed: " + e.what());
    return false;
  }
  if (on_switched_) on_switched_(on);
  return !cancelled_;  // the handler may have cancelled the schedule
}

void PowerCycleSchedule::start() {
  if (phase_ != Phase::Idle) return;
  cycle_ = 1;
  if (set_power(true)) enter(Phase::On, settings_.on);
}

void PowerCycleSchedule::enter(Phase phase, std::chrono::duration<double> length) {
  phase_ = phase;
  timer_.expires_after(std::chrono::duration_cast<Clock::duration>(length));
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || !running()) return;
    phase_ended();
  });
}

void PowerCycleSchedule::phase_ended() {
  if (phase_ == Phase::On) {
    if (set_power(false)) enter(Phase::Off, settings_.off);
    return;
  }
  if (cycle_ < settings_.cycles) {
    ++cycle_;
    if (set_power(true)) enter(Phase::On, settings_.on);
    return;
  }
  // The last cycle's cooling is over: the scanner goes back on, for service.
  if (!set_power(true)) return;
  phase_ = Phase::Finished;
  if (on_ended_) on_ended_(phase_, "");
}

void PowerCycleSchedule::cancel() {
  cancelled_ = true;
  if (!running()) return;
  phase_ = Phase::Cancelled;
  timer_.cancel();
  on_ended_ = nullptr;
  try {
    power_.set(true);
  } catch (const hal::GpioError&) {
    return;  // the switch is unusable; nothing else can restore the power
  }
  if (on_switched_) on_switched_(true);
}

PowerCycleSchedule::Progress PowerCycleSchedule::progress() const {
  Progress p{phase_, running() ? cycle_ : 0, settings_.cycles, 0.0};
  if (!running()) return p;
  const double phase_left =
      std::max(0.0, std::chrono::duration<double>(timer_.expiry() - Clock::now()).count());
  const double cycles_after = static_cast<double>(settings_.cycles - cycle_);
  p.time_left_s = phase_left + (phase_ == Phase::On ? settings_.off.count() : 0.0) +
                  cycles_after * (settings_.on.count() + settings_.off.count());
  return p;
}

std::string to_string(PowerCycleSchedule::Phase phase) {
  switch (phase) {
    case PowerCycleSchedule::Phase::Idle:
      return "idle";
    case PowerCycleSchedule::Phase::On:
      return "on";
    case PowerCycleSchedule::Phase::Off:
      return "off";
    case PowerCycleSchedule::Phase::Finished:
      return "finished";
    case PowerCycleSchedule::Phase::Failed:
      return "failed";
    case PowerCycleSchedule::Phase::Cancelled:
      return "cancelled";
  }
  return "?";
}

}  // namespace tofcomp::daemon
