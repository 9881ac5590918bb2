#include "daemon/scanner_link.hpp"

#include <spdlog/spdlog.h>

#include <utility>

#include "core/error.hpp"
#include "daemon/scan_conversion.hpp"
#include "settings/daemon_config_adapters.hpp"
#include "sim/lms200/emulated_scanner_device.hpp"
#include "sim/lms200/played_recording_device.hpp"

namespace tofcomp::daemon {

namespace {

// The configured device: the serial port, or the emulated LMS 200 (playing the recording when
// one is set; reporting its supply as the power unless a power sense is configured).
std::unique_ptr<hal::lms2xx::ScannerDevice> make_device(
    const settings::DaemonConfig& config, hal::lms2xx::ScannerDevice::Reports reports) {
  if (!config.emulator.enabled) {
    return std::make_unique<hal::lms2xx::SerialScannerDevice>(config.link.device.string());
  }
  auto emulator = std::make_unique<sim::lms200::Emulator>(settings::emulator_settings(config));
  const std::string scenario = config.emulator.scenario.string();
  if (!config.emulator.recording.empty()) {
    return std::make_unique<sim::lms200::PlayedRecordingDevice>(
        std::move(emulator), scenario, std::move(reports), config.link.scan_timeout);
  }
  return std::make_unique<sim::lms200::EmulatedScannerDevice>(
      std::move(emulator), scenario, std::move(reports), !config.power.sense.has_value());
}

}  // namespace

ScannerLink::ScannerLink(boost::asio::io_context& io, const settings::DaemonConfig& config,
                         const EventClock& clock, Handlers handlers)
    : link_config_(config.link),
      recording_(config.emulator.recording),
      clock_(clock),
      handlers_(std::move(handlers)),
      device_(make_device(config, {handlers_.recorded_case_reading, handlers_.power})) {
  device_->start();
  if (device_->in_process()) spdlog::info("{} on {}", device_->describe(), device_->path());
  hal::lms2xx::DriverSettings driver = settings::driver_settings(link_config_, device_->path());
  // An emulated device makes a new pty at each hang-up: the driver asks which at each opening
  // (a configuration without emulator.link has no stable path to give it).
  if (device_->in_process()) {
    driver.current_device = [device = device_.get()] { return device->path(); };
  }
  driver_ = std::make_unique<hal::lms2xx::Lms2xxDriver>(
      io, std::move(driver),
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

void ScannerLink::stop_device() {
  device_->stop();
}

void ScannerLink::reconnect_now() {
  driver_->reconnect_now();
}

void ScannerLink::housekeeping(Clock::time_point now) {
  device_->poll(clock_.seconds(now));
}

std::optional<std::filesystem::path> ScannerLink::played_recording() const {
  if (!device_->reports_case_readings()) return std::nullopt;
  return recording_;
}

std::function<double()> ScannerLink::case_sensor_source() const {
  if (auto source = device_->case_temperature()) return source;
  return []() -> double { throw core::Error("the simulated case sensor needs the emulator"); };
}

std::unique_ptr<hal::PowerSwitch> ScannerLink::supply_switch() const {
  std::unique_ptr<hal::GpioOutput> supply = device_->supply();
  if (!supply) return nullptr;
  const bool on = supply->get();
  return std::make_unique<hal::PowerSwitch>(std::move(supply), on);
}

void ScannerLink::on_scan(const hal::lms2xx::HostScan& host) {
  ArrivedScan arrived{to_raw_scan(host, link_config_.variant, 0.0), host.sequence, host.received,
                      std::nullopt};
  // The scan's time as the device has it (a played recording's, the events recorded before it
  // handed over first); else when it arrived.
  const hal::lms2xx::ScannerDevice::ScanTime when =
      device_->scan_arrived(arrived.raw.ranges_mm, arrived.raw.no_echo);
  if (when.unknown) spdlog::warn("scan {} is not one the playback sent", host.sequence);
  arrived.recorded_time_s = when.time_s;
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
