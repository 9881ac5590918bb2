// A tofcompd recording (io/recording_format.hpp) played back as the emulated LMS 200's
// scanner: the recorded scans in file order, the recorded case readings and power changes, on
// a clock that starts at the recording's first row. The emulator (sim/lms200/emulator.hpp)
// plays one instead of the digital twin, so that a replay through the emulator feeds the daemon
// the very scans and case temperatures it recorded.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "io/measurement_table.hpp"
#include "sim/twin.hpp"

namespace tofcomp::sim::lms200 {

class RecordingPlayback {
 public:
  // Throws core::InvalidInput naming `source` (and the line, where there is one) for a table
  // without the recording's geometry, with no scan or no case reading, with rows out of time
  // order, or with a beam outside the geometry or twice in one scan.
  RecordingPlayback(const io::MeasurementTable& table, const std::string& source);

  // Beams per scan, from the recording's metadata.
  std::size_t beams() const { return beams_; }
  std::size_t scan_count() const { return scans_.size(); }

  // The playback clock, in the recording's seconds; starts at the first row's time.
  double time_s() const { return time_s_; }
  // Moves the clock to `time_s`. Throws core::InvalidInput when it is in the past.
  void advance_to(double time_s);

  // The recorded power state now (the latest power row at or before now); on before the first.
  bool power_on() const;
  // The latest recorded case reading at or before now; the first one before any.
  double read_case_sensor() const;

  // The time of the next scan not yet played; nullopt when all were played.
  std::optional<double> next_scan_time() const;
  // The next scan not yet played, in order: one reading per beam, Valid with the recorded
  // range_mm, or NoEcho where the recording has no row for the beam (ground truth, bias and
  // mode are unknown and left 0). Does not move the clock. Throws core::Error when all scans
  // were played.
  std::vector<RangeReading> next_scan();

  // When the recorded state next changes: the next unplayed scan, or the next case reading or
  // power change after now. nullopt once every scan was played and the clock is at the end.
  std::optional<double> next_event_time() const;
  // Every scan played and the clock at the recording's last reading or power change.
  bool finished() const { return !next_event_time().has_value(); }

  // A recorded case reading or power change.
  struct Event {
    double time_s = 0.0;
    std::optional<double> case_c;
    std::optional<bool> power;
  };
  // The case readings and power changes at or before now that the recording holds before the
  // next unplayed scan, not taken yet, in file order: taken after each step of the clock and
  // after each scan played, they come in the recording's order relative to its scans.
  std::vector<Event> take_played_events();

 private:
  struct Scan {
    double time_s = 0.0;
    std::vector<double> ranges_mm;  // per beam; NaN: no echo
  };
  template <typename T>
  struct Timed {
    double time_s = 0.0;
    T value{};
  };

  std::size_t beams_ = 0;
  std::vector<Scan> scans_;
  std::vector<Timed<double>> case_readings_;
  std::vector<Timed<bool>> power_changes_;
  struct OrderedEvent {
    Event event;
    std::size_t scans_before = 0;  // the scans the file holds before it
  };
  std::vector<OrderedEvent> events_;  // case readings and power changes in file order
  std::size_t next_event_ = 0;        // the first not taken
  std::size_t next_scan_ = 0;
  double time_s_ = 0.0;
};

}  // namespace tofcomp::sim::lms200
