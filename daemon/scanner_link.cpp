#include "daemon/scanner_link.hpp"

#include <spdlog/spdlog.h>

#include <utility>

#include "core/error.hpp"
#include "daemon/emulator_power_line.hpp"
#include "daemon/scan_conversion.hpp"
#include "settings/daemon_config_adapters.hpp"

namespace tofcomp::daemon {

ScannerLink::ScannerLink(boost::asio::io_context& io, const settings::DaemonConfig& config,
                         const EventClock& clock, Handlers handlers)
    : link_config_(config.link),
      emulator_config_(config.emulator),
      power_sensed_(config.power.sense.has_value()),
      clock_(clock),
      handlers_(std::move(handlers)) {
  std::string device;
  if (emulator_config_.enabled) {
    emulator_ = std::make_unique<sim::lms200::Emulator>(settings::emulator_settings(config));
    if (!emulator_config_.recording.empty()) {
      // The recorded case readings and power changes, at their recorded times, in place of the
      // sensor poll and the emulator's power state.
      playback_ = std::make_unique<PlaybackFeed>(
          PlaybackFeed::Handlers{handlers_.recorded_case_reading, handlers_.power});
      PlaybackFeed* feed = playback_.get();
      emulator_->on_playback_event(
          [feed](const sim::lms200::PlaybackEvent& e) { feed->event_played(e); });
    }
    emulator_->start();
    device = emulator_->device_path();
    spdlog::info("emulated LMS 200 ({}) on {}", emulator_config_.scenario.string(), device);
  }
  driver_ = std::make_unique<hal::lms2xx::Lms2xxDriver>(
      io, settings::driver_settings(link_config_, device),
      [this](const hal::lms2xx::HostScan& s) { on_scan(s); },
      [this](hal::lms2xx::LinkState state, const std::string& why) { on_state(state, why); });
}

ScannerLink::~ScannerLink() = default;

void ScannerLink::start() {
  driver_->start();
}

void ScannerLink::stop() {
  driver_->stop();
}

void ScannerLink::stop_emulator() {
  if (emulator_) emulator_->stop();
}

void ScannerLink::reconnect_now() {
  driver_->reconnect_now();
}

void ScannerLink::housekeeping(Clock::time_point now) {
  if (playback_) {
    playback_->deliver(link_config_.scan_timeout);
  } else if (emulator_ && !power_sensed_) {
    handlers_.power(clock_.seconds(now), emulator_->power_on());
  }
}

std::optional<std::filesystem::path> ScannerLink::played_recording() const {
  if (!playback_) return std::nullopt;
  return emulator_config_.recording;
}

std::function<double()> ScannerLink::case_sensor_source() const {
  sim::lms200::Emulator* emulator = emulator_.get();
  return [emulator] {
    if (!emulator) throw core::Error("the simulated case sensor needs the emulator");
    return emulator->read_case_sensor();
  };
}

std::unique_ptr<hal::PowerSwitch> ScannerLink::emulated_supply_switch() const {
  if (!emulator_) return nullptr;
  return std::make_unique<hal::PowerSwitch>(std::make_unique<EmulatorPowerLine>(*emulator_),
                                            emulator_->power_on());
}

std::string ScannerLink::device() const {
  return emulator_ ? "emulated LMS 200 (" + emulator_config_.scenario.string() + ")"
                   : link_config_.device.string();
}

std::optional<sim::lms200::EmulatorCounters> ScannerLink::emulator_counters() const {
  if (!emulator_) return std::nullopt;
  return emulator_->counters();
}

void ScannerLink::on_scan(const hal::lms2xx::HostScan& host) {
  ArrivedScan arrived{to_raw_scan(host, link_config_.variant, 0.0), host.sequence, host.received,
                      std::nullopt};
  // Playing a recording, the scan's recorded time (the readings recorded before it are handed
  // over first); else when it arrived.
  if (playback_) {
    arrived.recorded_time_s = playback_->scan_arrived(arrived.raw);
    if (!arrived.recorded_time_s) {
      spdlog::warn("scan {} is not one the playback sent", host.sequence);
    }
  }
  handlers_.scan(std::move(arrived));
}

void ScannerLink::on_state(hal::lms2xx::LinkState state, const std::string& why) {
  state_ = hal::lms2xx::to_string(state) + ": " + why;
  if (handlers_.switched_off()) {
    // The daemon switched the scanner off: a silent link is expected, not a fault.
    state_ += " (the scanner is switched off)";
    spdlog::info("link: {}", state_);
  } else if (state == hal::lms2xx::LinkState::Backoff) {
    spdlog::warn("link: {}", state_);
  } else {
    spdlog::info("link: {}", state_);
  }
}

}  // namespace tofcomp::daemon
