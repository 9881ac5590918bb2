// tofcompd: one Boost.Asio event loop that takes scans from the LMS 200 link and readings from
// the case sensor, runs them through the compensation pipeline (realtime/), and publishes each
// compensated scan to the shared-memory ring and the Unix socket. Around it: the emulated
// LMS 200 of the embedded default, the recorder, the power-sense line, systemd's readiness and
// watchdog, SIGHUP reloads, and recalibration, which trains in a worker thread and swaps the
// new calibration in on the loop between two scans: on a recorded data set, or on the recording
// of a calibration run in which the daemon cycles the scanner's power (§8.1,
// daemon_calibration_run.cpp). Playing a recording through its emulator, it takes the recorded
// case readings and times from the playback (daemon/playback_feed.hpp).
#pragma once

#include <boost/asio.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "daemon/playback_feed.hpp"
#include "daemon/power_cycle_schedule.hpp"
#include "daemon/recorder.hpp"
#include "daemon/sensor_poller.hpp"
#include "daemon/service/systemd_notifier.hpp"
#include "daemon/socket/request_handler.hpp"
#include "daemon/socket/socket_server.hpp"
#include "hal/gpio/power_control.hpp"
#include "hal/lms2xx/host_driver.hpp"
#include "io/calibration_file.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "realtime/compensation_pipeline.hpp"
#include "settings/daemon_config.hpp"
#include "sim/lms200/emulator.hpp"

namespace tofcomp::daemon {

struct DaemonCounters {
  std::uint64_t scans_in = 0;         // from the link
  std::uint64_t scans_published = 0;  // to the ring and the socket
  std::uint64_t scans_rejected = 0;   // scans the pipeline refused (logged)
  std::uint64_t readings_valid = 0;
  std::uint64_t readings_invalid = 0;  // implausible, stale, missing: logged, not used
  std::uint64_t power_changes = 0;
  std::uint64_t reloads = 0;
  std::uint64_t reloads_refused = 0;
  std::uint64_t calibrations_swapped = 0;
  std::uint64_t recording_errors = 0;
};

class Daemon : public socket::SocketRequestHandler {
 public:
  // config_file: where reloads read from; empty: the configuration is the built-in default and
  // a reload re-reads that. Throws core::Error (naming what) when a part cannot start: the
  // calibration file, the ring, the socket, the emulator, the sensor backend.
  Daemon(settings::DaemonConfig config, std::filesystem::path config_file);
  ~Daemon() override;

  // Runs until SIGTERM or SIGINT (or stop()); returns the exit status.
  int run();
  // Thread-safe.
  void stop();

  // SocketRequestHandler, on the loop.
  const ipc::CompensatedScan* latest_scan() override;
  nlohmann::json status() override;
  nlohmann::json stats() override;
  socket::ReloadResult reload() override;
  socket::RecalibrationResult recalibrate(const nlohmann::json& args) override;

 private:
  double now_s(std::chrono::steady_clock::time_point t) const;
  double event_time(std::chrono::steady_clock::time_point t);
  void stop_recording(const std::string& why);
  void start_parts();
  void on_scan(const hal::lms2xx::HostScan& scan);
  void on_reading(std::chrono::steady_clock::time_point when, const hal::TemperatureReading& r);
  void take_case_reading(double time_s, double case_c);
  void on_power(double time_s, bool on);
  // Hands a row to each recorder running (the configured recording, a calibration run's); one
  // that fails is stopped, and a calibration run with it.
  void record(const std::function<void(Recorder&)>& write);
  void on_link_state(hal::lms2xx::LinkState state, const std::string& why);
  void watch_signals();
  void schedule_housekeeping();
  void use_calibration(std::shared_ptr<const core::Calibration> calibration,
                       const std::string& source);
  void finish_recalibration();
  void set_status(const std::string& text);

  boost::asio::io_context io_;
  boost::asio::signal_set signals_{io_};
  boost::asio::steady_timer housekeeping_{io_};
  settings::DaemonConfig config_;
  std::filesystem::path config_file_;
  std::chrono::steady_clock::time_point start_;
  service::SystemdNotifier notifier_;
  std::optional<std::chrono::steady_clock::duration> watchdog_period_;
  std::chrono::steady_clock::time_point last_watchdog_{};

  std::unique_ptr<sim::lms200::Emulator> emulator_;
  std::unique_ptr<hal::lms2xx::Lms2xxDriver> driver_;
  std::unique_ptr<SensorPoller> sensor_;    // null while playing a recording
  std::unique_ptr<PlaybackFeed> playback_;  // emulator.recording: readings and times
  std::unique_ptr<hal::PowerSense> power_sense_;
  std::unique_ptr<ipc::ring::RingWriter> ring_;
  std::unique_ptr<socket::SocketServer> server_;
  std::unique_ptr<Recorder> recorder_;
  realtime::CompensationPipeline pipeline_;

  std::optional<ipc::CompensatedScan> latest_;
  std::optional<bool> power_on_;
  std::optional<std::pair<double, double>> last_case_reading_;  // time_s, °C
  double last_scan_time_s_ = -1.0;
  double last_event_time_s_ = 0.0;
  std::string link_state_ = "starting";
  std::string sensor_state_ = "no reading yet";
  std::string last_reload_ = "none";
  std::string recalibration_state_ = "idle";
  std::string status_text_;
  std::uint32_t calibration_id_ = 0;
  std::string calibration_source_ = "none";
  bool ready_sent_ = false;
  DaemonCounters counters_;

  // Recalibration: one worker at a time; its result is taken on the loop.
  struct RecalibrationOutcome {
    std::string error;  // empty on success
    std::shared_ptr<const core::Calibration> calibration;
    std::filesystem::path file;
  };
  void start_recalibration(std::filesystem::path data, int beam);

  // The calibration run (§8.1), in daemon_calibration_run.cpp.
  hal::PowerSwitch& power_switch();
  std::string start_power_cycle_run();  // empty, or why it cannot start
  void on_run_switched(bool on);
  void on_run_ended(PowerCycleSchedule::Phase phase, const std::string& why);
  nlohmann::json calibration_run_status() const;
  std::unique_ptr<hal::PowerSwitch> power_switch_;  // made at the first run
  std::unique_ptr<Recorder> run_recorder_;
  std::unique_ptr<PowerCycleSchedule> run_;
  settings::PowerCycleRunConfig run_config_;  // the running one's (a reload may change the config)
  bool switched_off_ = false;                 // the daemon switched the scanner off
  std::thread worker_;
  bool worker_running_ = false;
  std::mutex outcome_mutex_;
  std::optional<RecalibrationOutcome> outcome_;  // set by the worker
};

}  // namespace tofcomp::daemon
