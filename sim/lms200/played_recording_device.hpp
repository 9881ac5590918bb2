// A recording played by the emulated LMS 200 (`emulator.recording`) as the device behind a host
// driver (hal/lms2xx/scanner_device.hpp): its playback feed (playback_feed.hpp) gives each scan
// that reaches the host its recorded time, and hands over the recorded case readings and power
// changes in the recording's order, in place of the host's sensor poll and the emulated supply.
// Owns the feed (and, as an EmulatedScannerDevice, the emulator).
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "sim/lms200/emulated_scanner_device.hpp"
#include "sim/lms200/playback_feed.hpp"

namespace tofcomp::sim::lms200 {

class PlayedRecordingDevice final : public EmulatedScannerDevice {
 public:
  // `emulator` plays a recording, not yet started. lost_after: a sent scan that has not reached
  // the host by then is taken as lost (PlaybackFeed::deliver).
  PlayedRecordingDevice(std::unique_ptr<Emulator> emulator, std::string scenario, Reports reports,
                        std::chrono::steady_clock::duration lost_after);
  ~PlayedRecordingDevice() override;  // stops the emulator before the feed goes

  ScanTime scan_arrived(std::span<const double> ranges_mm,
                        std::span<const std::uint8_t> no_echo) override;
  void poll(double now_s) override;
  bool reports_case_readings() const override { return true; }

 private:
  PlaybackFeed feed_;
  std::chrono::steady_clock::duration lost_after_;
};

}  // namespace tofcomp::sim::lms200
