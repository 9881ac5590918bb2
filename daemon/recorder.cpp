#include "daemon/recorder.hpp"

#include <ctime>
#include <system_error>

#include "core/error.hpp"
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
  if (out_) out_->flush();
}

void Recorder::write(const io::MeasurementRow& row) {
  if (!writer_) {
    before_first_scan_.push_back(row);
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
  if (out_) out_->flush();
  writer_.reset();
  out_.reset();
  std::filesystem::path path = settings_.directory / settings_.file_name;
  if (settings_.file_name.empty()) {
    path = settings_.directory / ("tofcompd-" + utc_stamp() + ".csv");
    for (int n = 1; std::filesystem::exists(path); ++n) {
      path = settings_.directory / ("tofcompd-" + utc_stamp() + "-" + std::to_string(n) + ".csv");
    }
  }
  std::vector<std::string> columns = io::recording_columns();
  if (settings_.true_range_mm) columns.emplace_back("true_range_mm");
  auto out = std::make_unique<std::ofstream>(path, std::ios::binary);
  if (!*out) throw core::Error("recording: cannot create " + path.string());
  const bool first_file = counters_.files == 0;
  writer_ = std::make_unique<io::MeasuredDataWriter>(
      *out,
      io::recording_metadata(first.ranges_mm.size(), first.start_angle_deg, first.resolution_deg),
      std::move(columns), path.string());
  out_ = std::move(out);
  current_path_ = path;
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
}

void Recorder::scan(const realtime::RawScan& scan) {
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
  out_->flush();
  if (!*out_) throw core::Error("recording: cannot write " + current_path_.string());
  ++counters_.scans;
}

}  // namespace tofcomp::daemon
