// The LMS 200 link: the host driver (hal/lms2xx/host_driver.hpp) on the configured device or on
// the in-process emulated LMS 200 (sim/lms200/emulator.hpp), and the link's state. Playing a
// recording (`emulator.recording`), the playback feed (daemon/playback_feed.hpp) gives each scan
// its recorded time and hands over the recorded case readings and power changes; else, without a
// power sense, the emulated scanner's supply is reported as its power. Owns the emulator, the
// playback feed, the driver and the link's state.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "daemon/arrived_scan.hpp"
#include "daemon/event_clock.hpp"
#include "daemon/playback_feed.hpp"
#include "hal/gpio/power_control.hpp"
#include "hal/lms2xx/host_driver.hpp"
#include "settings/daemon_config.hpp"
#include "sim/lms200/emulator.hpp"

namespace tofcomp::daemon {

class ScannerLink {
 public:
  using Clock = std::chrono::steady_clock;

  // Each runs on the loop.
  struct Handlers {
    std::function<void(ArrivedScan scan)> scan;
    // Playing a recording: a recorded case reading, at its recorded time.
    std::function<void(double time_s, double case_c)> recorded_case_reading;
    // The scanner's power as the recording or the emulated supply has it.
    std::function<void(double time_s, bool on)> power;
    // Whether the daemon switched the scanner off: the link's silence is expected then.
    std::function<bool()> switched_off;
  };

  // Starts the emulator when configured. Throws core::Error naming what cannot start.
  ScannerLink(boost::asio::io_context& io, const settings::DaemonConfig& config,
              const EventClock& clock, Handlers handlers);
  ~ScannerLink();
  ScannerLink(const ScannerLink&) = delete;
  ScannerLink& operator=(const ScannerLink&) = delete;

  // The driver brings the link up; stop() ends it.
  void start();
  void stop();
  void stop_emulator();
  // After the daemon switched the scanner on: connect now, not after the backoff.
  void reconnect_now();
  // On the loop's housekeeping: the played events no scan waits for, or the emulated supply.
  void housekeeping(Clock::time_point now);

  // The recording the emulator plays (whose case readings the playback hands over), if any.
  std::optional<std::filesystem::path> played_recording() const;
  // The simulated case sensor's source: the emulated scanner's case temperature.
  std::function<double()> case_sensor_source() const;
  // The emulated scanner's supply as a power switch; null without the emulator.
  std::unique_ptr<hal::PowerSwitch> emulated_supply_switch() const;

  const std::string& state() const { return state_; }
  // What the link runs on, for the status.
  std::string device() const;
  const hal::lms2xx::DriverCounters& driver_counters() const { return driver_->counters(); }
  std::optional<sim::lms200::EmulatorCounters> emulator_counters() const;

 private:
  void on_scan(const hal::lms2xx::HostScan& host);
  void on_state(hal::lms2xx::LinkState state, const std::string& why);

  settings::LinkConfig link_config_;
  settings::EmulatorConfig emulator_config_;
  bool power_sensed_;  // a power sense reports the power, not the emulated supply
  const EventClock& clock_;
  Handlers handlers_;
  std::unique_ptr<PlaybackFeed> playback_;  // emulator.recording: readings and times
  std::unique_ptr<sim::lms200::Emulator> emulator_;
  std::unique_ptr<hal::lms2xx::Lms2xxDriver> driver_;
  std::string state_ = "starting";
};

}  // namespace tofcomp::daemon
