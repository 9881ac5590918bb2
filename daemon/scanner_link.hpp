// The LMS 200 link: the host driver (hal/lms2xx/host_driver.hpp) and the device it talks to
// (hal/lms2xx/scanner_device.hpp): the configured serial port, or the emulated LMS 200 in this
// process, drawing from its twin or playing a recording (sim/lms200/). Every device is taken
// alike: it may give a scan its own time, report the scanner's power and the case readings, and
// have a case temperature and a supply to switch. Owns the device, the driver and the link's
// state.
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
#include "hal/gpio/power_control.hpp"
#include "hal/lms2xx/host_driver.hpp"
#include "hal/lms2xx/scanner_device.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

class ScannerLink {
 public:
  using Clock = std::chrono::steady_clock;

  // Each runs on the loop.
  struct Handlers {
    std::function<void(ArrivedScan scan)> scan;
    // A case reading the device reports (a played recording's), at its time.
    std::function<void(double time_s, double case_c)> recorded_case_reading;
    // The scanner's power as the device reports it (a recording, the emulated supply).
    std::function<void(double time_s, bool on)> power;
    // Whether the daemon switched the scanner off: the link's silence is expected then.
    std::function<bool()> switched_off;
  };

  // Starts an in-process device. Throws core::Error naming what cannot start.
  ScannerLink(boost::asio::io_context& io, const settings::DaemonConfig& config,
              const EventClock& clock, Handlers handlers);
  ~ScannerLink();
  ScannerLink(const ScannerLink&) = delete;
  ScannerLink& operator=(const ScannerLink&) = delete;

  // The driver brings the link up; stop() ends it.
  void start();
  void stop();
  void stop_device();
  // After the daemon switched the scanner on: connect now, not after the backoff.
  void reconnect_now();
  // On the loop's housekeeping: what the device has due.
  void housekeeping(Clock::time_point now);

  // The recording whose case readings the device reports, if it does.
  std::optional<std::filesystem::path> played_recording() const;
  // The simulated case sensor's source: the device's case temperature.
  std::function<double()> case_sensor_source() const;
  // The device's supply as a power switch; null when it has none to switch.
  std::unique_ptr<hal::PowerSwitch> supply_switch() const;

  const std::string& state() const { return state_; }
  // What the link runs on, for the status.
  std::string device() const { return device_->describe(); }
  const hal::lms2xx::DriverCounters& driver_counters() const { return driver_->counters(); }
  std::optional<hal::lms2xx::ScannerDevice::SentCounters> device_counters() const {
    return device_->sent_counters();
  }

 private:
  void on_scan(const hal::lms2xx::HostScan& host);
  void on_state(hal::lms2xx::LinkState state, const std::string& why);

  settings::LinkConfig link_config_;
  std::filesystem::path recording_;  // emulator.recording
  const EventClock& clock_;
  Handlers handlers_;
  std::unique_ptr<hal::lms2xx::ScannerDevice> device_;
  std::unique_ptr<hal::lms2xx::Lms2xxDriver> driver_;
  std::string state_ = "starting";
};

}  // namespace tofcomp::daemon
