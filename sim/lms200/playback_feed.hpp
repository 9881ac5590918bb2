// The host's side of a recording played by an emulated LMS 200 in its process
// (`emulator.recording`, played_recording_device.hpp): the recorded case readings and power
// changes, and the recorded time of each scan, taken from the playback instead of the daemon's own
// sensor poll and clock. A scan reaches the loop over the link some time after the emulator sent
// it; the feed keeps the played events in the recording's order, and when a scan arrives hands the
// pipeline first the readings and power changes recorded before it, then the scan at its recorded
// time. The pipeline then takes the very events, at the very times and in the very order, that the
// recording daemon took: its outputs are the recording daemon's (docs/daemon.md, "Recording and
// replay").
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "sim/lms200/emulator.hpp"

namespace tofcomp::sim::lms200 {

class PlaybackFeed {
 public:
  struct Handlers {
    std::function<void(double time_s, double case_c)> case_reading;
    std::function<void(double time_s, bool on)> power;
  };

  explicit PlaybackFeed(Handlers handlers);

  // From the emulator's thread (thread-safe): a case reading, power change or scan played.
  void event_played(const PlaybackEvent& event);

  // On the loop, for a scan that arrived over the link, by its ranges (mm) and no-echo flags
  // (1: no range) per beam: hands over the events recorded before it and returns its recorded
  // time. Sent scans before it that never arrived (lost on the
  // line) are passed over. nullopt when no sent scan has its ranges (its events stay queued).
  std::optional<double> scan_arrived(std::span<const double> ranges_mm,
                                     std::span<const std::uint8_t> no_echo);

  // On the loop: hands over the events not waiting behind a sent scan. A sent scan that has not
  // arrived within `lost_after` is taken as lost, so the events after it are not held forever.
  void deliver(std::chrono::steady_clock::duration lost_after);

 private:
  struct SentRanges {
    double time_s = 0.0;
    std::vector<double> ranges_mm;  // NaN: no echo
    std::chrono::steady_clock::time_point sent_at;
  };
  using Item = std::variant<PlaybackEvent, SentRanges>;

  void hand_over(const PlaybackEvent& event) const;
  static bool same_ranges(const SentRanges& sent, std::span<const double> ranges_mm,
                          std::span<const std::uint8_t> no_echo);

  Handlers handlers_;
  std::mutex mutex_;
  std::deque<Item> queue_;  // in the order the emulator played them
};

}  // namespace tofcomp::sim::lms200
