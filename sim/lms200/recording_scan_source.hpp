// The emulated LMS 200's scans played from a tofcompd recording (recording_playback.hpp): each
// recorded scan sent at its recorded time (scaled by time_scale), exactly as recorded, and the
// case sensor, power sense and clock answering from the recording. It sends what the recording
// holds and does not resample: the host must configure the recorded variant, or it receives
// scans of the wrong length. After the last scan no scan is sent. With hold_recorded_scans, a
// scan due while the host does not stream waits for it (and the playback clock waits with it).
// Each recorded case reading, power change and scan is reported to an observer as it is played,
// in the recording's order.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "io/measurement_table.hpp"
#include "sim/lms200/emulator.hpp"
#include "sim/lms200/recording_playback.hpp"
#include "sim/lms200/scan_source.hpp"

namespace tofcomp::sim::lms200 {

class RecordingScanSource : public ScanSource {
 public:
  // Throws core::InvalidInput naming `source` for a bad recording or one whose beams match no
  // LMS 200 variant (101, 181, 201, 361 or 401 values per scan).
  RecordingScanSource(const io::MeasurementTable& recording, const std::string& source,
                      double time_scale, bool hold_recorded_scans);

  // Set before the link starts; runs on the link's thread.
  void on_playback_event(Emulator::PlaybackObserver observer);

  bool power_on() const override;
  double read_case_sensor() override;
  double time_s() const override;
  void override_power(bool on) override;
  DrawnScan draw_scan(const Lms200Device& device) override;
  boost::asio::awaitable<void> stream(PtyLink& link) override;

 private:
  RecordingPlayback playback_;
  double time_scale_;
  bool hold_recorded_scans_;
  Emulator::PlaybackObserver observer_;
  DrawnScan queued_scan_;  // the recorded scan queued on the link, drawn when it is sent
  std::chrono::steady_clock::time_point origin_{};  // the wall time of the recording's start

  boost::asio::awaitable<void> send_recorded_scan(PtyLink& link);
  void report_played_events(PtyLink& link);
};

}  // namespace tofcomp::sim::lms200
