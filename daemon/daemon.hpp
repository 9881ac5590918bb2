// tofcompd: one Boost.Asio event loop that takes scans from the LMS 200 link and readings from
// the case sensor, runs them through the compensation pipeline (realtime/), and publishes each
// compensated scan to the shared-memory ring and the Unix socket. The work is the modules';
// the daemon makes them in order, wires them together, and runs the loop: signals, the
// housekeeping timer and the shutdown order.
//
//   running_config.hpp       the configuration and its reloads
//   event_clock.hpp          the pipeline's clock and the order of events
//   service_status.hpp       systemd's status, readiness, watchdog
//   recordings.hpp           the configured recording and a calibration run's
//   compensation_inputs.hpp  the pipeline, its calibration, the power state, the case readings
//   scanner_link.hpp         the driver and the device behind it (hal/lms2xx/scanner_device.hpp)
//   case_sensor_input.hpp    the case sensor's poll (or the recorded readings)
//   power_sense_input.hpp    the power-sense line
//   control.hpp              status, stats, reload and recalibration requests
//   scan_outputs.hpp         the ring, the socket server, the latest scan
//   recalibration.hpp        training in the worker, the swap, the power-cycle run (§8.1)
#pragma once

#include <boost/asio.hpp>
#include <filesystem>

#include "daemon/case_sensor_input.hpp"
#include "daemon/compensation_inputs.hpp"
#include "daemon/control.hpp"
#include "daemon/event_clock.hpp"
#include "daemon/power_sense_input.hpp"
#include "daemon/recalibration.hpp"
#include "daemon/recordings.hpp"
#include "daemon/running_config.hpp"
#include "daemon/scan_outputs.hpp"
#include "daemon/scanner_link.hpp"
#include "daemon/service_status.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

class Daemon {
 public:
  // config_file: where reloads read from; empty: the configuration is the built-in default and
  // a reload re-reads that. Throws core::Error (naming what) when a part cannot start: the
  // calibration file, the ring, the socket, the emulator, the sensor backend. `overrides`: the
  // command line's socket and ring, already applied to `config` and applied again at reloads.
  Daemon(settings::DaemonConfig config, std::filesystem::path config_file,
         settings::CommandLineOverrides overrides = {});
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  // Runs until SIGTERM or SIGINT (or stop()); returns the exit status.
  int run();
  // Thread-safe.
  void stop();

 private:
  void watch_signals();
  void schedule_housekeeping();
  // Removes what interrupted writes of the calibration files left; returns `config` unchanged.
  static settings::DaemonConfig after_removing_stale_temporaries(settings::DaemonConfig config);

  boost::asio::io_context io_;
  boost::asio::signal_set signals_{io_};
  boost::asio::steady_timer housekeeping_{io_};
  // The modules, in the order they start (and the reverse of the order they go).
  RunningConfig config_;
  EventClock clock_;
  ServiceStatus service_;
  Recordings recordings_;
  CompensationInputs inputs_;
  ScannerLink link_;
  CaseSensorInput sensor_;
  PowerSenseInput power_sense_;
  // Answers the socket of outputs_; it reads the modules made after it only from the loop.
  Control control_;
  ScanOutputs outputs_;
  Recalibration recalibration_;
};

}  // namespace tofcomp::daemon
