#include "daemon/recorder.hpp"

#include <unistd.h>

#include <cstring>
#include <ctime>
#include <system_error>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/recording_format.hpp"

namespace tofcomp::daemon {
namespace {

std::string utc_stamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", &tm);
  return text;
}

// Names tried for a rotation's file in one second before giving up: tofcompd-STAMP.csv, then
// tofcompd-STAMP-1.csv and on (taken names are skipped, whatever holds them).
constexpr int kMaxNamesPerStamp = 1000;

}  // namespace

Recorder::Recorder(RecorderSettings settings) : settings_(std::move(settings)) {
  std::error_code ec;
  std::filesystem::create_directories(settings_.directory, ec);
  if (ec) {
    throw core::Error("recording: cannot create the directory " + settings_.directory.string() +
                      ": " + ec.message());
  }
}

Recorder::~Recorder() {
  try {
    close_file();
  } catch (const core::Error&) {  // a destructor does not throw; the rows were counted as lost
  }
}

void Recorder::close_file() {
  if (!file_) return;
  writer_.reset();
  try {
    flush_whole();
  } catch (const core::Error&) {
    file_.reset();  // closed whether or not the last flush failed
    throw;
  }
  file_.reset();
}

void Recorder::flush_whole() {
  file_->flush();
  if (file_->error() == 0) {
    whole_bytes_ = file_->written();
    return;
  }
  // The file ends on its last whole scan, so that it still reads (a cut row would not).
  const bool cut = ::ftruncate(file_->fd(), static_cast<off_t>(whole_bytes_)) == 0;
  throw core::Error("recording: cannot write " + current_path_.string() + ": " +
                    std::strerror(file_->error()) +
                    (cut ? "; the file ends at its last whole scan" : ""));
}

void Recorder::abandon_file() {
  writer_.reset();
  file_.reset();
  if (whole_bytes_ == 0 && !current_path_.empty()) {
    std::error_code ignored;
    std::filesystem::remove(current_path_, ignored);
  }
}

void Recorder::write(const io::MeasurementRow& row) {
  if (!writer_) {
    // Before the first file, kept for it; while suspended, the state is kept (last_reading_,
    // power_on_) and the row is not recorded.
    if (counters_.files == 0) before_first_scan_.push_back(row);
    return;
  }
  writer_->write_row(row);
  ++rows_in_file_;
  ++counters_.rows;
}

void Recorder::case_reading(double time_s, double case_c) {
  last_reading_ = {time_s, case_c};
  write({.time_s = time_s, .case_temp_c = case_c});
}

void Recorder::power(double time_s, bool on) {
  power_on_ = on;
  write({.time_s = time_s, .power = on});
}

bool Recorder::rotation_due() const {
  if (!settings_.file_name.empty()) return false;
  if (settings_.max_rows && rows_in_file_ >= *settings_.max_rows) return true;
  return settings_.max_minutes && std::chrono::steady_clock::now() - opened_at_ >=
                                      std::chrono::minutes(*settings_.max_minutes);
}

void Recorder::open_file(const realtime::RawScan& first) {
  close_file();
  std::filesystem::path path = settings_.directory / settings_.file_name;
  int fd = -1;
  if (!settings_.file_name.empty()) {
    fd = io::replace_with_new_file(path);
  } else {
    const std::string stamp = utc_stamp();
    for (int n = 0; fd < 0; ++n) {
      if (n == kMaxNamesPerStamp) {
        throw core::Error("recording: " + std::to_string(kMaxNamesPerStamp) + " names tofcompd-" +
                          stamp + "*.csv are taken in " + settings_.directory.string());
      }
      path = settings_.directory /
             ("tofcompd-" + stamp + (n == 0 ? "" : "-" + std::to_string(n)) + ".csv");
      if (const auto created = io::create_new_file(path)) fd = *created;
    }
  }
  file_ = std::make_unique<io::DescriptorStream>(fd);
  whole_bytes_ = 0;
  current_path_ = path;
  std::vector<std::string> columns = io::recording_columns();
  if (settings_.true_range_mm) columns.emplace_back("true_range_mm");
  const bool first_file = counters_.files == 0;
  writer_ = std::make_unique<io::MeasuredDataWriter>(
      *file_,
      io::recording_metadata(first.ranges_mm.size(), first.start_angle_deg, first.resolution_deg),
      std::move(columns), path.string());
  opened_at_ = std::chrono::steady_clock::now();
  rows_in_file_ = 0;
  ++counters_.files;
  if (first_file) {
    // Everything the pipeline took before the first scan, in its order.
    std::vector<io::MeasurementRow> pending;
    pending.swap(before_first_scan_);
    for (const auto& row : pending) write(row);
  } else if (last_reading_) {
    // A file of its own: the state the pipeline is in.
    if (power_on_) write({.time_s = last_reading_->first, .power = *power_on_});
    write({.time_s = last_reading_->first, .case_temp_c = last_reading_->second});
  }
  flush_whole();  // the header and the state: what a cut file keeps at the least
}

void Recorder::scan(const realtime::RawScan& scan) {
  if (failed_at_s_ && scan.time_s - *failed_at_s_ < kRecorderRetryAfterS) {
    ++counters_.scans_lost;
    return;
  }
  try {
    if (!writer_ || rotation_due()) open_file(scan);
    std::vector<io::MeasurementRow> rows;
    io::append_scan_rows(scan.time_s, scan.ranges_mm, scan.no_echo, rows);
    for (auto& row : rows) {
      if (settings_.beams &&
          (*row.beam < settings_.beams->first || *row.beam > settings_.beams->second)) {
        continue;
      }
      row.true_range_mm = settings_.true_range_mm;
      write(row);
    }
    flush_whole();
  } catch (const core::Error&) {
    failed_at_s_ = scan.time_s;
    abandon_file();
    ++counters_.scans_lost;
    throw;
  }
  failed_at_s_.reset();
  ++counters_.scans;
}

}  // namespace tofcomp::daemon
