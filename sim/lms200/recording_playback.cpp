// Reads a recording's events into scans, case readings and power changes, and answers for them
// on the playback clock.
#include "sim/lms200/recording_playback.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "io/recording_format.hpp"

namespace tofcomp::sim::lms200 {
namespace {

// "source:line" for a row read from a file, "source, row N" for one built in memory.
std::string where(const std::string& source, const io::MeasurementRow& row, std::size_t index) {
  return row.line > 0 ? source + ":" + std::to_string(row.line)
                      : source + ", row " + std::to_string(index + 1);
}

// The last of the time-ordered `events` at or before `time_s`; nullptr when there is none.
template <typename Event>
const Event* latest_at(const std::vector<Event>& events, double time_s) {
  const auto after = std::upper_bound(events.begin(), events.end(), time_s,
                                      [](double t, const Event& e) { return t < e.time_s; });
  return after == events.begin() ? nullptr : &*(after - 1);
}

// The time of the first of `events` after `time_s`; nullopt when there is none.
template <typename Event>
std::optional<double> first_after(const std::vector<Event>& events, double time_s) {
  const auto after = std::upper_bound(events.begin(), events.end(), time_s,
                                      [](double t, const Event& e) { return t < e.time_s; });
  if (after == events.end()) return std::nullopt;
  return after->time_s;
}

}  // namespace

RecordingPlayback::RecordingPlayback(const io::MeasurementTable& table, const std::string& source)
    : beams_(io::read_recording_geometry(table, source).beams) {
  constexpr double kNoEcho = std::numeric_limits<double>::quiet_NaN();
  bool scan_open = false;
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const io::MeasurementRow& row = table.rows[i];
    if (i > 0 && row.time_s < table.rows[i - 1].time_s) {
      throw core::InvalidInput(where(source, row, i) + ": time_s " + std::to_string(row.time_s) +
                               " goes back in time");
    }
    if (!row.range_mm) {
      // As in a replay, any other event ends the scan being read.
      scan_open = false;
      if (row.power) power_changes_.push_back({row.time_s, *row.power});
      if (row.case_temp_c) case_readings_.push_back({row.time_s, *row.case_temp_c});
      if (row.power || row.case_temp_c) {
        events_.push_back({{row.time_s, row.case_temp_c, row.power}, scans_.size()});
      }
      continue;
    }
    if (!scan_open || row.time_s != scans_.back().time_s) {
      scans_.push_back({row.time_s, std::vector<double>(beams_, kNoEcho)});
      scan_open = true;
    }
    const int beam = row.beam.value_or(0);
    if (beam < 0 || static_cast<std::size_t>(beam) >= beams_) {
      throw core::InvalidInput(where(source, row, i) + ": beam " + std::to_string(beam) +
                               " outside the recording's " + std::to_string(beams_) + " beams");
    }
    double& range = scans_.back().ranges_mm[static_cast<std::size_t>(beam)];
    if (!std::isnan(range)) {
      throw core::InvalidInput(where(source, row, i) + ": beam " + std::to_string(beam) +
                               " appears twice in the scan at time_s " +
                               std::to_string(row.time_s));
    }
    range = *row.range_mm;
  }
  if (scans_.empty()) {
    throw core::InvalidInput(source + ": the recording holds no scan (no row with range_mm)");
  }
  if (case_readings_.empty()) {
    throw core::InvalidInput(source +
                             ": the recording holds no case_temp_c reading for the emulated "
                             "case sensor to report");
  }
  time_s_ = table.rows.front().time_s;
}

void RecordingPlayback::advance_to(double time_s) {
  if (!(time_s >= time_s_)) {
    throw core::InvalidInput("recording playback: cannot go back from " + std::to_string(time_s_) +
                             " s to " + std::to_string(time_s) + " s");
  }
  time_s_ = time_s;
}

bool RecordingPlayback::power_on() const {
  const auto* change = latest_at(power_changes_, time_s_);
  return change ? change->value : true;
}

double RecordingPlayback::read_case_sensor() const {
  const auto* reading = latest_at(case_readings_, time_s_);
  return reading ? reading->value : case_readings_.front().value;
}

std::optional<double> RecordingPlayback::next_scan_time() const {
  if (next_scan_ >= scans_.size()) return std::nullopt;
  return scans_[next_scan_].time_s;
}

std::vector<RangeReading> RecordingPlayback::next_scan() {
  if (next_scan_ >= scans_.size()) {
    throw core::Error("recording playback: all " + std::to_string(scans_.size()) +
                      " scans were played");
  }
  const Scan& scan = scans_[next_scan_++];
  std::vector<RangeReading> readings(beams_);
  for (std::size_t b = 0; b < beams_; ++b) {
    if (std::isnan(scan.ranges_mm[b])) {
      readings[b].status = ReadingStatus::NoEcho;
    } else {
      readings[b].range_mm = scan.ranges_mm[b];
    }
  }
  return readings;
}

std::vector<RecordingPlayback::Event> RecordingPlayback::take_played_events() {
  std::vector<Event> taken;
  while (next_event_ < events_.size() && events_[next_event_].event.time_s <= time_s_ &&
         events_[next_event_].scans_before <= next_scan_) {
    taken.push_back(events_[next_event_++].event);
  }
  return taken;
}

std::optional<double> RecordingPlayback::next_event_time() const {
  std::optional<double> next = next_scan_time();
  for (const std::optional<double> t :
       {first_after(case_readings_, time_s_), first_after(power_changes_, time_s_)}) {
    if (t && (!next || *t < *next)) next = t;
  }
  return next;
}

}  // namespace tofcomp::sim::lms200
