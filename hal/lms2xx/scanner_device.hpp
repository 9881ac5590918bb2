// The scanner behind the host driver's serial line (host_driver.hpp), as the host sees it: a real
// LMS 2xx on a serial port (SerialScannerDevice, below), or one emulated in the host's process
// (sim/lms200/emulated_scanner_device.hpp: the twin's, or a recording's playback). Besides where
// the driver opens it, a device may keep the scans' times (a played recording), report the
// scanner's power and the case readings it knows, measure the case temperature, and give its
// supply to switch. The host treats every device alike.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "hal/gpio/gpio_line.hpp"

namespace tofcomp::hal::lms2xx {

class ScannerDevice {
 public:
  // What a device reports besides its scans, on the host's loop, each at a time in seconds on
  // the host's clock (a played recording's times stand in for it).
  struct Reports {
    std::function<void(double time_s, double case_c)> case_reading;
    std::function<void(double time_s, bool on)> power;
  };

  // When a scan that reached the host was measured, as the device has it.
  struct ScanTime {
    std::optional<double> time_s;  // nullopt: the host's arrival time stands
    bool unknown = false;          // the device keeps the scans' times, but sent no such scan
  };

  // What an emulated device counts of what it sent.
  struct SentCounters {
    std::uint64_t scans_sent = 0;
    std::uint64_t scans_skipped = 0;  // scans the line rate could not carry
    std::uint64_t telegrams_sent = 0;
    std::uint64_t faults_injected = 0;
    // The faults injected, each kind by its name (what the device's configuration calls it).
    std::vector<std::pair<std::string, std::uint64_t>> faults_by_kind;
  };

  virtual ~ScannerDevice() = default;

  // Brings an in-process device up (throws core::Error when it cannot); a real one is there.
  virtual void start() {}
  virtual void stop() {}
  // Where the host driver opens it.
  virtual std::string path() const = 0;
  // What it is, for the host's status.
  virtual std::string describe() const = 0;
  // Whether it runs in the host's process (the host announces it when it starts).
  virtual bool in_process() const { return false; }

  // A scan that reached the host, by its ranges (mm) and no-echo flags (1: no range) per beam.
  virtual ScanTime scan_arrived(std::span<const double> ranges_mm,
                                std::span<const std::uint8_t> no_echo) {
    static_cast<void>(ranges_mm);
    static_cast<void>(no_echo);
    return {};
  }
  // Every housekeeping period, on the host's loop (now_s on its clock): reports what is due.
  virtual void poll(double now_s) { static_cast<void>(now_s); }

  // Whether it reports the case readings (Reports::case_reading): no sensor is polled then.
  virtual bool reports_case_readings() const { return false; }
  // The case temperature it measures (a simulated sensor's source); empty: none.
  virtual std::function<double()> case_temperature() const { return {}; }
  // Its supply as an output to switch (now on); null: the host cannot switch it this way.
  virtual std::unique_ptr<GpioOutput> supply() { return nullptr; }
  virtual std::optional<SentCounters> sent_counters() const { return std::nullopt; }
};

// A real LMS 2xx on a serial port.
class SerialScannerDevice final : public ScannerDevice {
 public:
  explicit SerialScannerDevice(std::string path) : path_(std::move(path)) {}

  std::string path() const override { return path_; }
  std::string describe() const override { return path_; }

 private:
  std::string path_;
};

}  // namespace tofcomp::hal::lms2xx
