#include "daemon/daemon.hpp"

#include <spdlog/spdlog.h>

#include <csignal>
#include <exception>
#include <utility>
#include <vector>

#include "io/atomic_file.hpp"

namespace tofcomp::daemon {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

// The housekeeping's period: the watchdog's pings, the emulated supply's polling, the played
// events no scan waits for, a finished recalibration.
constexpr std::chrono::milliseconds kHousekeepingPeriod{100};

Daemon::Daemon(settings::DaemonConfig config, std::filesystem::path config_file,
               settings::CommandLineOverrides overrides)
    // The stale temporaries go first, before the socket appears: a client that sees the socket
    // sees the directory as the daemon will keep it.
    : config_(after_removing_stale_temporaries(std::move(config)), std::move(config_file),
              std::move(overrides)),
      recordings_([this](const std::string& why) { recalibration_.run_recording_failed(why); }),
      inputs_(config_.current(), clock_, recordings_),
      link_(io_, config_.current(), clock_,
            ScannerLink::Handlers{
                [this](ArrivedScan scan) {
                  if (auto out = inputs_.scan(std::move(scan))) {
                    outputs_.publish(std::move(*out));
                  } else if (const auto& why = inputs_.refusal()) {
                    service_.scan_refused(*why);
                  }
                },
                [this](double time_s, double case_c) { sensor_.recorded(time_s, case_c); },
                [this](double time_s, bool on) { inputs_.power(time_s, on); },
                [this] { return inputs_.switched_off(); }}),
      sensor_(io_, config_.current().case_sensor, link_.played_recording(),
              link_.case_sensor_source(), clock_,
              [this](double time_s, double case_c) { inputs_.case_reading(time_s, case_c); }),
      power_sense_(io_, config_.current().power.sense, clock_,
                   [this](double time_s, bool on) { inputs_.power(time_s, on); }),
      control_(Control::Modules{config_, clock_, service_, link_, sensor_, inputs_, recordings_,
                                outputs_, recalibration_}),
      outputs_(io_, config_.current().outputs, control_, service_),
      recalibration_(io_, config_,
                     PowerCycleRun::Parts{link_, inputs_, recordings_, service_, clock_}) {
  recordings_.configure(config_.current().recording);
  spdlog::info("publishing to shm {} and socket {}", outputs_.ring().name(),
               outputs_.socket_path());
}

// The temporary files interrupted calibration writes left beside the files the daemon writes
// (io/atomic_file.hpp): removed at start, before any write.
settings::DaemonConfig Daemon::after_removing_stale_temporaries(settings::DaemonConfig config) {
  std::vector<std::filesystem::path> files = {config.calibration.file,
                                              config.recalibration.output};
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (files[i].empty() || (i > 0 && files[i] == files[0])) continue;
    for (const auto& removed : io::remove_stale_temporaries(files[i])) {
      spdlog::info("removed {}, left by an interrupted write of {}", removed.string(),
                   files[i].string());
    }
  }
  return config;
}

Daemon::~Daemon() {
  recalibration_.stop();
  sensor_.stop();
  link_.stop_device();
}

int Daemon::run() {
  watch_signals();
  service_.start_watchdog();
  sensor_.start();
  link_.start();
  schedule_housekeeping();
  service_.show_scan_state();
  recalibration_.start_if_missing();
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
  service_.stopping();
  recalibration_.cancel_run();
  link_.stop();
  sensor_.stop();
  outputs_.stop();
  link_.stop_device();
  spdlog::info("stopped after {} scans", outputs_.scans_published());
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
      const socket::ReloadResult r = control_.reload();
      (r.ok ? spdlog::info("SIGHUP: {}", r.message) : spdlog::error("SIGHUP: {}", r.message));
      watch_signals();
      return;
    }
    spdlog::info("signal {}: stopping", signal);
    io_.stop();
  });
}

// On the loop, so that a stuck loop stops the watchdog's pings.
void Daemon::schedule_housekeeping() {
  housekeeping_.expires_after(kHousekeepingPeriod);
  housekeeping_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    const auto now = Clock::now();
    service_.watchdog(now);
    link_.housekeeping(now);
    recalibration_.finish();
    schedule_housekeeping();
  });
}

}  // namespace tofcomp::daemon
