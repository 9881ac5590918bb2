// The daemon's recording of what it took in (io/recording_format.hpp): case
// readings, power changes and raw scans, in the order the pipeline took them, into the
// interchange CSV, one file per rotation period in the configured directory. Each file starts
// with the last case reading and power state, so it can be trained on or replayed alone; the
// first file replays to the very outputs the daemon published. Written on the event loop,
// flushed after every scan, so a crash loses at most the scan being written.
//
// The directory may be writable by others: a file is always made new (never opened through a
// symlink or over a file planted there; a calibration run's named file replaces what is there
// by a rename). A write that fails (a full disk) cuts the file back to its last whole scan, so
// that it still reads, and names the system's error; the scans of the next
// kRecorderRetryAfterS are not recorded (counted lost), then a new file is tried, starting with
// the pipeline's state.
//
// A calibration run's recording (§8.1, daemon/power_cycle_run.hpp) is one such recording in one
// named file, of the beams that face the target only, each range with the target's known
// distance (true_range_mm) for training.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "io/descriptor_stream.hpp"
#include "io/measured_data_csv.hpp"
#include "realtime/raw_scan.hpp"

namespace tofcomp::daemon {

struct RecorderSettings {
  std::filesystem::path directory;
  std::optional<long> max_rows;     // a new file after this many rows
  std::optional<long> max_minutes;  // or after this long
  // One file of this name (in `directory`, replaced by a rename if it exists) and no rotation;
  // empty: a timestamped name per rotation.
  std::filesystem::path file_name = {};
  // Only the beams first to last (inclusive); nullopt: every beam.
  std::optional<std::pair<int, int>> beams = std::nullopt;
  // Each range's reference distance (the true_range_mm column); nullopt: not known, no column.
  std::optional<double> true_range_mm = std::nullopt;
};

// After a failed write, the scan time (seconds) before a new file is tried.
inline constexpr double kRecorderRetryAfterS = 10.0;

struct RecorderCounters {
  std::uint64_t rows = 0;
  std::uint64_t files = 0;
  std::uint64_t scans = 0;
  std::uint64_t scans_lost = 0;  // not recorded: the one whose write failed, and those after it
};

class Recorder {
 public:
  // Creates the directory. Throws core::Error naming it when it cannot.
  explicit Recorder(RecorderSettings settings);
  ~Recorder();

  void case_reading(double time_s, double case_c);
  void power(double time_s, bool on);
  // Throws core::Error naming the file and the system's error when it cannot be written; the
  // recorder goes on (see above).
  void scan(const realtime::RawScan& scan);
  // True between a failed write and the next file's opening.
  bool suspended() const { return failed_at_s_.has_value(); }

  const std::filesystem::path& current_file() const { return current_path_; }
  const RecorderCounters& counters() const { return counters_; }

 private:
  void open_file(const realtime::RawScan& first);
  void close_file();
  // After a failure: closes the file as it is (cut already), removed when it holds nothing.
  void abandon_file();
  // Flushes; on a failed write cuts the file back to its last whole scan and throws
  // core::Error naming the file and the system's error.
  void flush_whole();
  void write(const io::MeasurementRow& row);
  bool rotation_due() const;

  RecorderSettings settings_;
  std::unique_ptr<io::DescriptorStream> file_;  // the recording being written; null while none
  std::uint64_t whole_bytes_ = 0;  // the file's bytes up to its last whole scan
  std::optional<double> failed_at_s_;  // the scan time of the last failed write
  std::unique_ptr<io::MeasuredDataWriter> writer_;
  std::filesystem::path current_path_;
  std::chrono::steady_clock::time_point opened_at_{};
  long rows_in_file_ = 0;
  std::vector<io::MeasurementRow> before_first_scan_;      // written when the first file opens
  std::optional<std::pair<double, double>> last_reading_;  // time_s, °C
  std::optional<bool> power_on_;
  double last_time_s_ = 0.0;
  RecorderCounters counters_;
};

}  // namespace tofcomp::daemon
