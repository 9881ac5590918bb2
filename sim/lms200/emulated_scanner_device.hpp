// The emulated LMS 200 (emulator.hpp) as the device behind a host driver
// (hal/lms2xx/scanner_device.hpp): where the host opens its pty, its case temperature (the
// simulated sensor's source), its supply to switch (emulator_power_line.hpp), its counters, and,
// at each poll, the twin scanner's power (unless the host senses the power itself).
// PlayedRecordingDevice (played_recording_device.hpp) is the same emulator playing a recording.
// Owns the emulator.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "hal/lms2xx/scanner_device.hpp"
#include "sim/lms200/emulator.hpp"

namespace tofcomp::sim::lms200 {

class EmulatedScannerDevice : public hal::lms2xx::ScannerDevice {
 public:
  // scenario: the twin's scenario, for the description. report_power: whether polls report the
  // scanner's power (not when the host senses it).
  EmulatedScannerDevice(std::unique_ptr<Emulator> emulator, std::string scenario, Reports reports,
                        bool report_power);
  ~EmulatedScannerDevice() override;  // stop()

  void start() override;
  void stop() override;
  std::string path() const override;
  std::string describe() const override;
  bool in_process() const override { return true; }
  void poll(double now_s) override;
  std::function<double()> case_temperature() const override;
  std::unique_ptr<hal::GpioOutput> supply() override;
  std::optional<SentCounters> sent_counters() const override;

 protected:
  Emulator& emulator() { return *emulator_; }
  const Reports& reports() const { return reports_; }

 private:
  std::unique_ptr<Emulator> emulator_;
  std::string scenario_;
  Reports reports_;
  bool report_power_;
};

}  // namespace tofcomp::sim::lms200
