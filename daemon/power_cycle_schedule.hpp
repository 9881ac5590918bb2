// The power schedule of a calibration run (§8.1 of the paper: several on-off cycles of the
// scanner, its case temperature logged, a target at a known distance): on for on_s, off for
// off_s, `cycles` times, then on again. It switches a hal::PowerSwitch on the Asio loop with a
// timer (it never blocks) and reports each switching and its end. The daemon records around it
// and trains on the recording (daemon/power_cycle_run.hpp).
//
//   idle -> cycle 1 on -> cycle 1 off -> ... -> cycle n off -> finished (power on again)
//                     \-> failed (the switch failed)   \-> cancelled (power on again)
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <string>

#include "hal/gpio/power_control.hpp"

namespace tofcomp::daemon {

class PowerCycleSchedule {
 public:
  enum class Phase { Idle, On, Off, Finished, Failed, Cancelled };

  struct Settings {
    int cycles = 1;
    std::chrono::duration<double> on{1.0};
    std::chrono::duration<double> off{1.0};
  };

  struct Progress {
    Phase phase = Phase::Idle;
    int cycle = 0;  // 1 to cycles while on or off; 0 when idle
    int cycles = 0;
    double time_left_s = 0.0;  // until the schedule ends
  };

  // Called on the loop after each successful switching, with the new state.
  using Switched = std::function<void(bool on)>;
  // Called on the loop once, when the schedule ends: Finished, or Failed with the reason.
  using Ended = std::function<void(Phase phase, const std::string& why)>;

  // Throws core::InvalidInput for fewer than one cycle or a duration that is not positive.
  PowerCycleSchedule(boost::asio::io_context& io, hal::PowerSwitch& power, Settings settings,
                     Switched on_switched, Ended on_ended);
  ~PowerCycleSchedule();  // cancel()
  PowerCycleSchedule(const PowerCycleSchedule&) = delete;
  PowerCycleSchedule& operator=(const PowerCycleSchedule&) = delete;

  // Switches the power on and starts cycle 1. Once only.
  void start();
  // Stops a running schedule and switches the power back on (Switched reports it; when the
  // switch fails, it does not). Ended is not called.
  void cancel();

  Progress progress() const;
  bool running() const { return phase_ == Phase::On || phase_ == Phase::Off; }

 private:
  void enter(Phase phase, std::chrono::duration<double> length);
  void phase_ended();
  bool set_power(bool on);

  boost::asio::steady_timer timer_;
  hal::PowerSwitch& power_;
  Settings settings_;
  Switched on_switched_;
  Ended on_ended_;
  Phase phase_ = Phase::Idle;
  int cycle_ = 0;
  bool cancelled_ = false;
};

// "idle", "on", "off", "finished", "failed", "cancelled".
std::string to_string(PowerCycleSchedule::Phase phase);

}  // namespace tofcomp::daemon
