// The emulated LMS 200 on a pseudo-terminal: the device model (sim/lms200/device.hpp) answering
// a host over a real pty (sim/lms200/pty_link.hpp), scans drawn from the digital twin in real
// time or faster (sim/lms200/twin_scan_source.hpp), the link's rate honoured (bytes at a rate
// other than the host's are lost, as on a real line), and faults injected at configured rates.
// Runs its own thread; `tofcomp emulate` serves one until stopped.
//
// With a recording set, the device plays it (sim/lms200/recording_scan_source.hpp) instead of
// the twin: each recorded scan is sent at its recorded time (scaled by time_scale), exactly as
// recorded, and the case sensor, power sense and clock answer from the recording. The device
// sends what the recording holds and does not resample: the host must configure the recorded
// variant (the one whose values per scan equal the recording's `beams`), or it receives scans
// of the wrong length. After the last scan the link stays up but no scan is sent. With
// hold_recorded_scans, no recorded scan is lost: one due while the host does not stream waits
// for it (and the playback clock waits with it). Each recorded case reading, power change and
// scan is reported to an observer as it is played, in the recording's order, so that a daemon
// in the same process can take them at their recorded instants.
//
// set_power() is the scanner's supply switch: off stops the scans and the twin's laser heat
// input, on restarts the device, which announces itself as after a power-on; the host brings it
// up again.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hal/lms2xx/commands.hpp"
#include "io/measurement_table.hpp"
#include "sim/lms200/device.hpp"
#include "sim/lms200/fault_injector.hpp"
#include "sim/scenario.hpp"
#include "sim/twin.hpp"

namespace tofcomp::sim::lms200 {

class PtyLink;
class RecordingScanSource;

struct EmulatorSettings {
  // The twin's experiment. Playing a recording, the twin is built but not played (the scenario
  // must still be valid).
  Scenario scenario;
  DeviceIdentity identity;
  // Twin seconds per wall-clock second; 0 runs as fast as the host reads (no pacing at the
  // line rate, no scans skipped), for tests and replays.
  double time_scale = 1.0;
  FaultRates faults;
  std::uint64_t fault_seed = 1;
  // A stable path for hosts (a symlink to the current pty); empty: hosts use the pty's path.
  std::filesystem::path link;
  double restart_s = 0.1;  // wall-clock seconds from a reset to the power-on telegram
  // A tofcompd recording to play instead of the twin, and its name for error messages. Its
  // `beams` must be the values per scan of an LMS 200 variant (101, 181, 201, 361 or 401).
  std::optional<io::MeasurementTable> recording;
  std::string recording_source = "recording";
  // Playing a recording: hold a recorded scan due while the host does not stream (or the line
  // is busy) until it does, pausing the playback clock, instead of skipping it. Without a host
  // the playback then waits at the first scan.
  bool hold_recorded_scans = false;
};

// A recorded case reading, power change or scan, as the playback passes it.
struct PlaybackEvent {
  double time_s = 0.0;           // the recording's time
  std::optional<double> case_c;  // a case reading
  std::optional<bool> power;     // a power change
  // A scan handed to the line: its ranges per beam (NaN: no echo); empty for the others.
  std::vector<double> scan_ranges_mm = {};
};

// A scan as the twin drew it (or the recording held it) and the device sent it (before any fault
// was applied to its bytes).
struct SentScan {
  std::uint64_t sequence = 0;  // counts every scan sent, from 0
  double twin_time_s = 0.0;    // playing a recording: the scan's recorded time
  const std::vector<RangeReading>* readings = nullptr;  // valid during the callback only
  hal::lms2xx::Units units = hal::lms2xx::Units::Millimetre;
  LinkFault fault = LinkFault::None;
  // The true time of beam 0's ray. The emulated device measures the scan's last ray as its
  // telegram starts on the line, and (at time_scale 1) the telegram reaches the host when the
  // line at its rate would have carried its last byte, as with the LMS 2xx; the sweep before
  // the last ray follows the variant (hal/lms2xx/scan_timing.hpp).
  std::chrono::system_clock::time_point first_ray;
};

struct EmulatorCounters {
  std::uint64_t scans_sent = 0;
  std::uint64_t scans_skipped = 0;  // scans the line rate could not carry
  std::uint64_t telegrams_sent = 0;
  std::uint64_t requests = 0;  // host telegrams with a good CRC
  std::uint64_t naks_sent = 0;
  std::uint64_t bytes_lost_to_rate_mismatch = 0;
  std::uint64_t bytes_unheard_while_restarting = 0;  // the host's, during a reset's restart_s
  InjectedFaults injected;
  std::string failure;             // set when the emulator stopped on an error
  bool playback_finished = false;  // a recording was played to its end: no more scans come
};

class Emulator {
 public:
  using ScanObserver = std::function<void(const SentScan&)>;
  using FaultObserver = std::function<void(LinkFault, std::chrono::steady_clock::time_point)>;
  using PlaybackObserver = std::function<void(const PlaybackEvent&)>;

  // Throws core::InvalidInput for a bad scenario, fault rates or recording (one whose beams
  // match no LMS 200 variant).
  explicit Emulator(EmulatorSettings settings);
  ~Emulator();
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;

  // Observers run on the emulator's thread; set them before start().
  void on_scan_sent(ScanObserver observer);
  void on_fault(FaultObserver observer);
  // Playing a recording: each recorded case reading, power change and scan as it is played, in
  // the recording's order (a scan when it is queued for the line, before any event after it).
  void on_playback_event(PlaybackObserver observer);

  // Opens the pty and starts serving. Throws core::Error when the pty cannot be opened.
  void start();
  void stop();

  // Where a host opens the device: the link when configured, else the pty's own path.
  std::string device_path() const;
  EmulatorCounters counters() const;
  // The case sensor on the twin's scanner, now (thread-safe): the simulated temperature backend.
  // Playing a recording: the latest recorded reading.
  double read_case_sensor();
  // The twin's clock, seconds since the scenario began; playing a recording, its clock.
  double twin_time_s() const;
  // Whether the twin's scanner is powered now (thread-safe): the simulated power sense.
  // Playing a recording: the recorded power state. After set_power(), the switch's state.
  bool power_on() const;
  // Switches the scanner's supply (thread-safe), from now on whatever the scenario's schedule or
  // the recording says: off stops the scans and the twin's laser heat input (u = 0, Eq. 4);
  // on powers the device up again (a restart, then its power-on telegram).
  void set_power(bool on);

 private:
  RecordingScanSource* recording_ = nullptr;  // the source, when playing a recording
  std::unique_ptr<PtyLink> link_;
};

}  // namespace tofcomp::sim::lms200
