// The daemon's recording of what it took in (io/recording_format.hpp): case
// readings, power changes and raw scans, in the order the pipeline took them, into the
// interchange CSV, one file per rotation period in the configured directory. Each file starts
// with the last case reading and power state, so it can be trained on or replayed alone; the
// first file replays to the very outputs the daemon published. Written on the event loop,
// flushed after every scan, so a crash loses at most the scan being written.
//
// A calibration run's recording (§8.1, daemon/power_cycle_run.hpp) is one such recording in one
// named file, of the beams that face the target only, each range with the target's known
// distance (true_range_mm) for training.
#pragma once

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "io/measured_data_csv.hpp"
#include "realtime/raw_scan.hpp"

namespace tofcomp::daemon {

struct RecorderSettings {
  std::filesystem::path directory;
  std::optional<long> max_rows;     // a new file after this many rows
  std::optional<long> max_minutes;  // or after this long
  // One file of this name (in `directory`, replaced if it exists) and no rotation; empty: a
  // timestamped name per rotation.
  std::filesystem::path file_name = {};
  // Only the beams first to last (inclusive); nullopt: every beam.
  std::optional<std::pair<int, int>> beams = std::nullopt;
  // Each range's reference distance (the true_range_mm column); nullopt: not known, no column.
  std::optional<double> true_range_mm = std::nullopt;
};

struct RecorderCounters {
  std::uint64_t rows = 0;
  std::uint64_t files = 0;
  std::uint64_t scans = 0;
};

class Recorder {
 public:
  // Creates the directory. Throws core::Error naming it when it cannot.
  explicit Recorder(RecorderSettings settings);
  ~Recorder();

  void case_reading(double time_s, double case_c);
  void power(double time_s, bool on);
  // Throws core::Error naming the file when it cannot be written.
  void scan(const realtime::RawScan& scan);

  const std::filesystem::path& current_file() const { return current_path_; }
  const RecorderCounters& counters() const { return counters_; }

 private:
  void open_file(const realtime::RawScan& first);
  void write(const io::MeasurementRow& row);
  bool rotation_due() const;

  RecorderSettings settings_;
  std::unique_ptr<std::ofstream> out_;
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
