#include "daemon/daemon.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <csignal>

#include "core/error.hpp"
#include "daemon/scan_conversion.hpp"
#include "hal/sensors/sensor_config.hpp"
#include "io/calibration_file.hpp"
#include "settings/daemon_config_adapters.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::daemon {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

Daemon::Daemon(settings::DaemonConfig config, std::filesystem::path config_file)
    : config_(std::move(config)),
      config_file_(std::move(config_file)),
      start_(Clock::now()),
      pipeline_(settings::pipeline_settings(config_)) {
  const bool missing =
      !config_.calibration.file.empty() && !std::filesystem::exists(config_.calibration.file);
  if (missing &&
      config_.recalibration.trigger == settings::RecalibrationTrigger::AtStartIfMissing) {
    spdlog::warn("calibration {} missing: recalibrating at start",
                 config_.calibration.file.string());
    use_calibration(nullptr, "none");
  } else {
    use_calibration(settings::read_configured_calibration(config_),
                    config_.calibration.file.string());
  }
  start_parts();
}

Daemon::~Daemon() {
  if (worker_.joinable()) worker_.join();
  run_.reset();
  if (sensor_) sensor_->stop();
  if (emulator_) emulator_->stop();
}

double Daemon::now_s(Clock::time_point t) const {
  return std::chrono::duration<double>(t - start_).count();
}

// The pipeline's time of an event: its own time, or the last event's if that is later (a case
// reading is stamped when its read returned, and may reach the loop after a later scan). The
// pipeline and the recording then see time run forwards only.
double Daemon::event_time(Clock::time_point t) {
  last_event_time_s_ = std::max(now_s(t), last_event_time_s_);
  return last_event_time_s_;
}

void Daemon::stop_recording(const std::string& why) {
  ++counters_.recording_errors;
  spdlog::error("recording stopped: {}", why);
  recorder_.reset();
}

void Daemon::record(const std::function<void(Recorder&)>& write) {
  if (recorder_) {
    try {
      write(*recorder_);
    } catch (const core::Error& e) {
      stop_recording(e.what());
    }
  }
  if (run_recorder_) {
    try {
      write(*run_recorder_);
    } catch (const core::Error& e) {
      ++counters_.recording_errors;
      run_recorder_.reset();
      if (run_) run_->cancel();
      on_run_ended(PowerCycleSchedule::Phase::Failed,
                   std::string("the run's recording failed: ") + e.what());
    }
  }
}

// Swaps a calibration in (on the loop, between two scans: no scan is lost or mixed).
void Daemon::use_calibration(std::shared_ptr<const core::Calibration> calibration,
                             const std::string& source) {
  if (!calibration) {
    if (calibration_id_ != 0) pipeline_.clear_calibration();
    calibration_source_ = "none";
    spdlog::warn("no calibration configured: publishing raw ranges, flagged uncalibrated");
    return;
  }
  pipeline_.set_calibration(std::move(calibration), calibration_id_ + 1);
  ++calibration_id_;
  ++counters_.calibrations_swapped;
  calibration_source_ = source;
  const core::Calibration* in_use = pipeline_.calibration();
  spdlog::info("calibration {} in use, from {}{}", calibration_id_, source,
               in_use && in_use->extension
                   ? ", with the " + io::effect_token(in_use->extension->effect) + " extension"
                   : std::string());
}

void Daemon::start_parts() {
  std::string device;
  if (config_.emulator.enabled) {
    emulator_ = std::make_unique<sim::lms200::Emulator>(settings::emulator_settings(config_));
    if (!config_.emulator.recording.empty()) {
      // The recorded case readings and power changes, at their recorded times, in place of the
      // sensor poll and the emulator's power state.
      playback_ = std::make_unique<PlaybackFeed>(
          PlaybackFeed::Handlers{[this](double t, double c) {
                                   ++counters_.readings_valid;
                                   sensor_state_ = "valid";
                                   take_case_reading(t, c);
                                 },
                                 [this](double t, bool on) { on_power(t, on); }});
      PlaybackFeed* feed = playback_.get();
      emulator_->on_playback_event(
          [feed](const sim::lms200::PlaybackEvent& e) { feed->event_played(e); });
    }
    emulator_->start();
    device = emulator_->device_path();
    spdlog::info("emulated LMS 200 ({}) on {}", config_.emulator.scenario.string(), device);
  }
  driver_ = std::make_unique<hal::lms2xx::Lms2xxDriver>(
      io_, settings::driver_settings(config_.link, device),
      [this](const hal::lms2xx::HostScan& s) { on_scan(s); },
      [this](hal::lms2xx::LinkState state, const std::string& why) { on_link_state(state, why); });

  sim::lms200::Emulator* emulator = emulator_.get();
  if (!playback_) {
    auto sensor = hal::make_temperature_sensor(config_.case_sensor.sensor, [emulator] {
      if (!emulator) throw core::Error("the simulated case sensor needs the emulator");
      return emulator->read_case_sensor();
    });
    sensor_ = std::make_unique<SensorPoller>(
        io_, std::move(sensor), config_.case_sensor.poll_interval,
        [this](Clock::time_point when, const hal::TemperatureReading& r) { on_reading(when, r); });
  }

  if (config_.power.sense) {
    power_sense_ = hal::make_power_sense(
        io_, *config_.power.sense,
        [this](const hal::GpioEdge& edge) { on_power(now_s(Clock::now()), edge.rising); },
        [](const std::string& why) { spdlog::error("power sense: {}", why); });
    on_power(now_s(Clock::now()), power_sense_->level());
  }

  const auto& shm = config_.outputs.shm;
  ring_ = std::make_unique<ipc::ring::RingWriter>(shm.name, static_cast<std::uint32_t>(shm.slots),
                                                  ipc::ring::kDefaultMaxBeams,
                                                  ipc::ring::RingWriterOptions{shm.mode, false});
  const auto& so = config_.outputs.socket;
  if (so.path.has_parent_path()) {
    std::error_code ignored;  // a failure shows when the server binds, naming the path
    std::filesystem::create_directories(so.path.parent_path(), ignored);
  }
  socket::SocketServerSettings settings;
  settings.path = so.path.string();
  settings.permissions = so.mode;
  settings.max_clients = static_cast<std::size_t>(so.max_clients);
  settings.max_request_bytes = so.max_request_bytes;
  settings.max_queued_bytes_per_client = so.max_queued_bytes_per_client;
  server_ = std::make_unique<socket::SocketServer>(
      io_, settings, *this, [](socket::SocketLogLevel level, const std::string& message) {
        if (level == socket::SocketLogLevel::Warning) {
          spdlog::warn("{}", message);
        } else {
          spdlog::info("{}", message);
        }
      });
  server_->start();
  if (config_.recording.enabled) {
    recorder_ = std::make_unique<Recorder>(RecorderSettings{
        config_.recording.directory, config_.recording.max_rows, config_.recording.max_minutes});
  }
  spdlog::info("publishing to shm {} and socket {}", shm.name, settings.path);
}

int Daemon::run() {
  watch_signals();
  if (const auto interval = notifier_.watchdog_interval()) {
    watchdog_period_ = service::SystemdNotifier::ping_period(*interval);
  }
  if (sensor_) sensor_->start();
  driver_->start();
  schedule_housekeeping();
  set_status("waiting for the first scan");
  if (calibration_id_ == 0 &&
      config_.recalibration.trigger == settings::RecalibrationTrigger::AtStartIfMissing) {
    if (config_.recalibration.source == settings::RecalibrationSource::Recording) {
      start_recalibration(config_.recalibration.data, 0);
    } else if (config_.recalibration.source == settings::RecalibrationSource::PowerCycleRun) {
      const std::string refused = start_power_cycle_run();
      if (!refused.empty()) spdlog::error("recalibration at start: {}", refused);
    }
  }
  // A handler that throws is a bug: it is logged and the loop goes on, so one bad event never
  // stops the service.
  for (;;) {
    try {
      io_.run();
      break;
    } catch (const std::exception& e) {
      spdlog::error("event loop: {}", e.what());
    }
  }
  notifier_.stopping();
  // A calibration run cut short leaves the scanner powered.
  if (run_ && run_->running()) {
    spdlog::info("power-cycle run cancelled: switching the scanner back on");
    run_->cancel();
  }
  driver_->stop();
  if (sensor_) sensor_->stop();
  if (server_) server_->stop();
  if (emulator_) emulator_->stop();
  spdlog::info("stopped after {} scans", counters_.scans_published);
  return 0;
}

void Daemon::stop() {
  asio::post(io_, [this] { io_.stop(); });
}

void Daemon::watch_signals() {
  signals_.add(SIGINT);
  signals_.add(SIGTERM);
  signals_.add(SIGHUP);
  signals_.async_wait([this](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    if (signal == SIGHUP) {
      const socket::ReloadResult r = reload();
      (r.ok ? spdlog::info("SIGHUP: {}", r.message) : spdlog::error("SIGHUP: {}", r.message));
      watch_signals();
      return;
    }
    spdlog::info("signal {}: stopping", signal);
    io_.stop();
  });
}

// Every 100 ms on the loop: the watchdog ping (so a stuck loop stops the pings), the emulated
// scanner's power state (or, playing a recording, the played events no scan waits for), a
// finished recalibration.
void Daemon::schedule_housekeeping() {
  housekeeping_.expires_after(std::chrono::milliseconds(100));
  housekeeping_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    const auto now = Clock::now();
    if (watchdog_period_ && now - last_watchdog_ >= *watchdog_period_) {
      notifier_.watchdog();
      last_watchdog_ = now;
    }
    if (playback_) {
      playback_->deliver(config_.link.scan_timeout);
    } else if (emulator_ && !power_sense_) {
      const bool on = emulator_->power_on();
      if (power_on_ != on) on_power(now_s(now), on);
    }
    finish_recalibration();
    schedule_housekeeping();
  });
}

void Daemon::on_power(double time_s, bool on) {
  if (power_on_ == on) return;
  power_on_ = on;
  ++counters_.power_changes;
  const double t = std::max(time_s, last_event_time_s_);
  last_event_time_s_ = t;
  pipeline_.on_power(t, on);
  record([&](Recorder& r) { r.power(t, on); });
  spdlog::info("scanner power {}", on ? "on" : "off");
}

void Daemon::on_reading(Clock::time_point when, const hal::TemperatureReading& r) {
  if (!r.valid()) {
    ++counters_.readings_invalid;
    sensor_state_ = std::string(hal::to_string(r.validity)) + ": " + r.detail;
    spdlog::warn("case sensor: {}", sensor_state_);
    return;
  }
  ++counters_.readings_valid;
  sensor_state_ = "valid";
  take_case_reading(event_time(when), r.celsius);
}

void Daemon::take_case_reading(double time_s, double case_c) {
  const double t = std::max(time_s, last_event_time_s_);
  last_event_time_s_ = t;
  last_case_reading_ = {t, case_c};
  pipeline_.on_case_reading(t, case_c);
  record([&](Recorder& r) { r.case_reading(t, case_c); });
}

void Daemon::on_link_state(hal::lms2xx::LinkState state, const std::string& why) {
  link_state_ = hal::lms2xx::to_string(state) + ": " + why;
  if (switched_off_) {
    // The daemon switched the scanner off: a silent link is expected, not a fault.
    link_state_ += " (the scanner is switched off)";
    spdlog::info("link: {}", link_state_);
  } else if (state == hal::lms2xx::LinkState::Backoff) {
    spdlog::warn("link: {}", link_state_);
  } else {
    spdlog::info("link: {}", link_state_);
  }
}

void Daemon::on_scan(const hal::lms2xx::HostScan& host) {
  ++counters_.scans_in;
  realtime::RawScan raw = to_raw_scan(host, config_.link.variant, 0.0);
  // Playing a recording, the scan's recorded time (the readings recorded before it are handed
  // over first); else when it arrived.
  const std::optional<double> recorded = playback_ ? playback_->scan_arrived(raw) : std::nullopt;
  if (playback_ && !recorded) spdlog::warn("scan {} is not one the playback sent", host.sequence);
  // Scans that arrived in one read share a timestamp; each gets a time of its own, so that a
  // recording keeps them apart (io/recording_format.hpp).
  double t = recorded ? std::max(*recorded, last_event_time_s_) : event_time(host.received);
  if (t <= last_scan_time_s_) t = std::nextafter(last_scan_time_s_, INFINITY);
  last_scan_time_s_ = t;
  last_event_time_s_ = t;
  raw.time_s = t;
  // A scan proves the scanner is powered, whatever the last sense said; but one that reaches
  // the loop after the daemon switched the power off was measured before: it is published, and
  // left out of the recordings (a data set holds no range while the power is 0).
  const bool measured_before_switch_off = power_on_ == false && switched_off_;
  if (power_on_ == false && !switched_off_) on_power(t, true);
  ipc::CompensatedScan out;
  try {
    out = pipeline_.on_scan(raw);
  } catch (const core::Error& e) {
    ++counters_.scans_rejected;
    spdlog::error("scan {} not published: {}", host.sequence, e.what());
    return;
  }
  if (!measured_before_switch_off) record([&](Recorder& r) { r.scan(raw); });
  ring_->publish(out);
  server_->publish(out);
  latest_ = std::move(out);
  ++counters_.scans_published;
  if (!ready_sent_) {
    ready_sent_ = true;
    notifier_.ready();
    spdlog::info("first compensated scan published: ready");
    set_status("publishing compensated scans");
  }
}

void Daemon::set_status(const std::string& text) {
  status_text_ = text;
  notifier_.status(text);
}

const ipc::CompensatedScan* Daemon::latest_scan() {
  return latest_ ? &*latest_ : nullptr;
}

}  // namespace tofcomp::daemon
