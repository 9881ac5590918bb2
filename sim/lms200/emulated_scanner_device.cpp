#include "sim/lms200/emulated_scanner_device.hpp"

#include <utility>

#include "sim/lms200/emulator_power_line.hpp"

namespace tofcomp::sim::lms200 {

EmulatedScannerDevice::EmulatedScannerDevice(std::unique_ptr<Emulator> emulator,
                                             std::string scenario, Reports reports,
                                             bool report_power)
    : emulator_(std::move(emulator)),
      scenario_(std::move(scenario)),
      reports_(std::move(reports)),
      report_power_(report_power) {}

EmulatedScannerDevice::~EmulatedScannerDevice() {
  stop();
}

void EmulatedScannerDevice::start() {
  emulator_->start();
}

void EmulatedScannerDevice::stop() {
  emulator_->stop();
}

std::string EmulatedScannerDevice::path() const {
  return emulator_->device_path();
}

std::string EmulatedScannerDevice::describe() const {
  return "emulated LMS 200 (" + scenario_ + ")";
}

void EmulatedScannerDevice::poll(double now_s) {
  if (report_power_) reports_.power(now_s, emulator_->power_on());
}

std::function<double()> EmulatedScannerDevice::case_temperature() const {
  Emulator* emulator = emulator_.get();
  return [emulator] { return emulator->read_case_sensor(); };
}

std::unique_ptr<hal::GpioOutput> EmulatedScannerDevice::supply() {
  return std::make_unique<EmulatorPowerLine>(*emulator_);
}

std::optional<hal::lms2xx::ScannerDevice::SentCounters> EmulatedScannerDevice::sent_counters()
    const {
  const EmulatorCounters c = emulator_->counters();
  return SentCounters{c.scans_sent, c.scans_skipped, c.telegrams_sent, c.injected.total(),
                      c.injected.by_kind()};
}

}  // namespace tofcomp::sim::lms200
