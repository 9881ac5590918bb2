#include "sim/lms200/recording_scan_source.hpp"

#include <algorithm>
#include <limits>
#include <mutex>
#include <optional>

#include "core/error.hpp"
#include "hal/lms2xx/commands.hpp"
#include "sim/lms200/pty_link.hpp"

namespace tofcomp::sim::lms200 {

using Clock = std::chrono::steady_clock;

namespace {
// The playback, when an LMS 200 variant carries its scans.
RecordingPlayback playback_of(const io::MeasurementTable& recording, const std::string& source) {
  RecordingPlayback playback(recording, source);
  for (const hal::lms2xx::Variant v :
       {hal::lms2xx::Variant{100, 25}, hal::lms2xx::Variant{100, 50},
        hal::lms2xx::Variant{100, 100}, hal::lms2xx::Variant{180, 50},
        hal::lms2xx::Variant{180, 100}}) {
    if (static_cast<std::size_t>(v.values_per_scan()) == playback.beams()) return playback;
  }
  throw core::InvalidInput(source + ": the recording's " + std::to_string(playback.beams()) +
                           " beams match no LMS 200 variant (101, 181, 201, 361 or 401 values)");
}
}  // namespace

RecordingScanSource::RecordingScanSource(const io::MeasurementTable& recording,
                                         const std::string& source, double time_scale,
                                         bool hold_recorded_scans)
    : playback_(playback_of(recording, source)),
      time_scale_(time_scale),
      hold_recorded_scans_(hold_recorded_scans) {}

void RecordingScanSource::on_playback_event(Emulator::PlaybackObserver observer) {
  observer_ = std::move(observer);
}

bool RecordingScanSource::power_on() const {
  return playback_.power_on();
}

double RecordingScanSource::read_case_sensor() {
  return playback_.read_case_sensor();
}

double RecordingScanSource::time_s() const {
  return playback_.time_s();
}

// The recording's power state gives way to the switch in stream() (PtyLink::switched_power).
void RecordingScanSource::override_power(bool) {}

DrawnScan RecordingScanSource::draw_scan(const Lms200Device&) {
  return queued_scan_;
}

// Steps the playback from event to event (scans, case readings, power changes) at their recorded
// times, scaled; at time_scale 0 as fast as the host reads, each scan held until the host streams
// and each event until the line is idle.
boost::asio::awaitable<void> RecordingScanSource::stream(PtyLink& link) {
  origin_ = Clock::now();
  const double recording_start = playback_.time_s();
  for (;;) {
    std::optional<double> due;
    {
      std::lock_guard lock(link.state_mutex());
      due = playback_.next_event_time();
    }
    if (!due) {
      link.mark_playback_finished();
      co_await link.wait_for_host(std::chrono::hours(1));
      continue;
    }
    if (time_scale_ > 0.0) {
      const Clock::time_point at = origin_ + wall_duration((*due - recording_start) / time_scale_);
      if (Clock::now() < at) {
        co_await link.wait_for_host(at - Clock::now());
        continue;  // maybe woken early by a request
      }
    } else if (!link.idle()) {
      co_await link.wait_for_host(std::chrono::milliseconds(20));
      continue;
    }
    bool on = false;
    bool scan_due = false;
    {
      std::lock_guard lock(link.state_mutex());
      playback_.advance_to(std::max(*due, playback_.time_s()));
      on = link.switched_power().value_or(playback_.power_on());
      const std::optional<double> next_scan = playback_.next_scan_time();
      scan_due = next_scan && *next_scan <= playback_.time_s();
    }
    report_played_events(link);
    link.switch_power(on);
    if (scan_due) co_await send_recorded_scan(link);
  }
}

// Hands the case readings and power changes the playback has passed, in the recording's order,
// to the observer.
void RecordingScanSource::report_played_events(PtyLink& link) {
  std::vector<RecordingPlayback::Event> events;
  {
    std::lock_guard lock(link.state_mutex());
    events = playback_.take_played_events();
  }
  if (!observer_) return;
  for (const auto& e : events) observer_(PlaybackEvent{e.time_s, e.case_c, e.power, {}});
}

// Takes the next recorded scan and queues it if the device streams and the line is free; at
// time_scale 0, or holding recorded scans, it waits for both first (a hold pauses the playback
// clock).
boost::asio::awaitable<void> RecordingScanSource::send_recorded_scan(PtyLink& link) {
  if (time_scale_ == 0.0 || hold_recorded_scans_) {
    const Clock::time_point held_from = Clock::now();
    while (link.powered() && !(link.device().streaming() && link.idle() && link.rates_match())) {
      co_await link.wait_for_host(std::chrono::milliseconds(20));
    }
    origin_ += Clock::now() - held_from;
  }
  DrawnScan scan;
  {
    std::lock_guard lock(link.state_mutex());
    scan.time_s = *playback_.next_scan_time();
    scan.readings = playback_.next_scan();
  }
  if (!link.powered() || !link.device().streaming()) {
    // Not sent: the device is off, or no host streams.
  } else if (link.idle()) {
    queued_scan_ = std::move(scan);  // idle: the link holds no scan it has yet to draw
    link.queue_scan();
    if (observer_) {
      PlaybackEvent sent{queued_scan_.time_s, std::nullopt, std::nullopt, {}};
      for (const RangeReading& r : queued_scan_.readings) {
        sent.scan_ranges_mm.push_back(r.status == ReadingStatus::Valid
                                          ? r.range_mm
                                          : std::numeric_limits<double>::quiet_NaN());
      }
      observer_(sent);
    }
  } else {
    link.count_skipped_scan();
  }
  report_played_events(link);  // those recorded after the scan at its very time
}

}  // namespace tofcomp::sim::lms200
