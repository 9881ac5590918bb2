#include "sim/lms200/played_recording_device.hpp"

#include <utility>

namespace tofcomp::sim::lms200 {

PlayedRecordingDevice::PlayedRecordingDevice(std::unique_ptr<Emulator> emulator,
                                             std::string scenario, Reports reports,
                                             std::chrono::steady_clock::duration lost_after)
    : EmulatedScannerDevice(std::move(emulator), std::move(scenario), reports, false),
      feed_(PlaybackFeed::Handlers{reports.case_reading, reports.power}),
      lost_after_(lost_after) {
  PlaybackFeed* feed = &feed_;
  this->emulator().on_playback_event([feed](const PlaybackEvent& e) { feed->event_played(e); });
}

PlayedRecordingDevice::~PlayedRecordingDevice() {
  stop();
}

hal::lms2xx::ScannerDevice::ScanTime PlayedRecordingDevice::scan_arrived(
    std::span<const double> ranges_mm, std::span<const std::uint8_t> no_echo) {
  ScanTime time;
  time.time_s = feed_.scan_arrived(ranges_mm, no_echo);
  time.unknown = !time.time_s;
  return time;
}

void PlayedRecordingDevice::poll(double now_s) {
  static_cast<void>(now_s);
  feed_.deliver(lost_after_);
}

}  // namespace tofcomp::sim::lms200
