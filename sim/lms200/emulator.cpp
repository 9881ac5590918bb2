#include "sim/lms200/emulator.hpp"

#include <algorithm>
#include <atomic>
#include <boost/asio.hpp>
#include <deque>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "core/error.hpp"
#include "sim/lms200/pty_port.hpp"
#include "sim/lms200/recording_playback.hpp"

namespace tofcomp::sim::lms200 {

namespace asio = boost::asio;
using asio::awaitable;
using asio::use_awaitable;
using Clock = std::chrono::steady_clock;

namespace {
std::chrono::nanoseconds seconds(double s) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(s));
}

// The recording's playback, when the settings hold one whose scans an LMS 200 variant carries.
std::optional<RecordingPlayback> playback_of(const EmulatorSettings& settings) {
  if (!settings.recording) return std::nullopt;
  RecordingPlayback playback(*settings.recording, settings.recording_source);
  for (const hal::lms2xx::Variant v :
       {hal::lms2xx::Variant{100, 25}, hal::lms2xx::Variant{100, 50},
        hal::lms2xx::Variant{100, 100}, hal::lms2xx::Variant{180, 50},
        hal::lms2xx::Variant{180, 100}}) {
    if (static_cast<std::size_t>(v.values_per_scan()) == playback.beams()) return playback;
  }
  throw core::InvalidInput(settings.recording_source + ": the recording's " +
                           std::to_string(playback.beams()) +
                           " beams match no LMS 200 variant (101, 181, 201, 361 or 401 values)");
}
}  // namespace

class Emulator::Server {
 public:
  explicit Server(EmulatorSettings settings)
      : settings_(std::move(settings)),
        twin_(settings_.scenario),
        recording_(playback_of(settings_)),
        device_(settings_.identity),
        injector_(settings_.faults, settings_.fault_seed) {
    if (settings_.time_scale < 0.0) {
      throw core::InvalidInput(
          "emulator: time_scale must be 0 (as fast as the host reads) or "
          "positive, not " +
          std::to_string(settings_.time_scale));
    }
  }

  ~Server() { stop(); }

  void start() {
    open_pty();
    powered_ = recording_ ? recording_->power_on() : twin_.power_on();
    if (powered_) enqueue_send(device_.power_on_telegram());
    asio::co_spawn(io_, reader(generation_), failure_reporter("reader"));
    asio::co_spawn(io_, writer(), failure_reporter("writer"));
    asio::co_spawn(io_, recording_ ? play_recording() : streamer(), failure_reporter("streamer"));
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() {
    if (!thread_.joinable()) return;
    io_.stop();
    thread_.join();
    if (master_.is_open()) static_cast<void>(master_.release());
    pty_.reset();
    if (!settings_.link.empty()) {
      std::error_code ec;
      std::filesystem::remove(settings_.link, ec);
    }
  }

  std::string device_path() const {
    std::lock_guard lock(mutex_);
    return settings_.link.empty() ? (pty_ ? pty_->slave_path() : std::string())
                                  : settings_.link.string();
  }

  EmulatorCounters counters() const {
    std::lock_guard lock(mutex_);
    EmulatorCounters c = counters_;
    c.injected = injector_.injected();
    c.requests = device_.decoder_counters().telegrams;
    c.naks_sent = device_.naks_sent();
    return c;
  }

  double read_case_sensor() {
    std::lock_guard lock(mutex_);
    return recording_ ? recording_->read_case_sensor() : twin_.read_case_sensor();
  }

  double twin_time_s() const {
    std::lock_guard lock(mutex_);
    return recording_ ? recording_->time_s() : twin_.time_s();
  }

  bool power_on() const {
    const int switched = power_switch_;
    return switched >= 0 ? switched == 1 : powered_.load();
  }

  void set_power(bool on) {
    power_switch_ = on ? 1 : 0;
    asio::post(io_, [this, on] {
      {
        std::lock_guard lock(mutex_);
        twin_.set_power_override(on);
      }
      switch_power(on);
    });
  }

  ScanObserver scan_observer;
  FaultObserver fault_observer;
  PlaybackObserver playback_observer;

 private:
  EmulatorSettings settings_;
  // Guards the twin, the recording, the device and the counters against readers.
  mutable std::mutex mutex_;
  Twin twin_;
  std::optional<RecordingPlayback> recording_;  // played instead of the twin when set
  std::vector<RangeReading> recorded_scan_;     // the recorded scan due to be sent
  double recorded_scan_time_ = 0.0;             // and its recorded time
  Clock::time_point playback_origin_{};         // the wall time of the recording's start
  Lms200Device device_;
  FaultInjector injector_;
  EmulatorCounters counters_;
  asio::io_context io_;
  std::thread thread_;
  std::unique_ptr<PtyPort> pty_;
  asio::posix::stream_descriptor master_{io_};
  std::uint64_t generation_ = 0;  // bumped on each hang-up: the old reader ends
  std::deque<DeviceOutput> queue_;
  bool writing_ = false;
  std::atomic<bool> powered_ = false;   // read by power_on() from other threads
  std::atomic<int> power_switch_ = -1;  // set_power(): 1 on, 0 off; -1 never switched
  asio::steady_timer wake_writer_{io_, Clock::time_point::max()};
  asio::steady_timer wake_streamer_{io_, Clock::time_point::max()};
  Clock::time_point stalled_until_{};

  void open_pty() {
    auto pty = std::make_unique<PtyPort>();
    if (!settings_.link.empty()) publish_symlink(settings_.link, pty->slave_path());
    if (master_.is_open()) static_cast<void>(master_.release());
    master_.assign(pty->master_fd());
    std::lock_guard lock(mutex_);
    pty_ = std::move(pty);
  }

  void hang_up() {
    ++generation_;
    boost::system::error_code ignored;
    master_.cancel(ignored);
    static_cast<void>(master_.release());
    pty_->close();
    queue_.clear();
    open_pty();
    asio::co_spawn(io_, reader(generation_), failure_reporter("reader"));
  }

  // A coroutine that ends with an exception stops the device: the error is kept for
  // counters() and the io_context stops, so a failure is never silent.
  std::function<void(std::exception_ptr)> failure_reporter(const char* part) {
    return [this, part](std::exception_ptr error) {
      if (!error) return;
      try {
        std::rethrow_exception(error);
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        counters_.failure = std::string("emulator ") + part + ": " + e.what();
      }
      io_.stop();
    };
  }

  bool rates_match() const { return pty_->host_baud() == device_.baud(); }

  void enqueue(DeviceOutput output) {
    queue_.push_back(std::move(output));
    wake_writer_.cancel();
  }
  void enqueue_send(std::vector<std::uint8_t> bytes) {
    enqueue(DeviceOutput{DeviceOutput::Action::Send, std::move(bytes), 0});
  }
  bool idle() const { return queue_.empty() && !writing_; }

  awaitable<void> reader(std::uint64_t generation) {
    std::vector<std::uint8_t> buffer(4096);
    std::vector<DeviceOutput> outputs;
    for (;;) {
      boost::system::error_code ec;
      const std::size_t n = co_await master_.async_read_some(
          asio::buffer(buffer), asio::redirect_error(use_awaitable, ec));
      if (generation != generation_) co_return;
      if (ec) {
        // EIO while no host holds the slave open: wait and read again.
        asio::steady_timer pause(io_, std::chrono::milliseconds(5));
        co_await pause.async_wait(asio::redirect_error(use_awaitable, ec));
        if (generation != generation_) co_return;
        continue;
      }
      if (!powered_ || !rates_match()) {
        std::lock_guard lock(mutex_);
        counters_.bytes_lost_to_rate_mismatch += n;
        continue;
      }
      outputs.clear();
      {
        std::lock_guard lock(mutex_);
        device_.receive(std::span(buffer.data(), n), outputs);
      }
      for (auto& o : outputs) enqueue(std::move(o));
      wake_streamer_.cancel();
    }
  }

  awaitable<void> wait(asio::steady_timer& timer, Clock::duration d) {
    timer.expires_after(d);
    boost::system::error_code ec;
    co_await timer.async_wait(asio::redirect_error(use_awaitable, ec));
  }

  std::vector<std::uint8_t> draw_scan(LinkFault* fault_slot, std::vector<RangeReading>& readings) {
    std::lock_guard lock(mutex_);
    if (recording_) {
      readings = recorded_scan_;
    } else {
      twin_.set_output(device_.scanner_output(settings_.scenario.scanner));
      readings = twin_.scan();
    }
    static_cast<void>(fault_slot);
    return device_.scan_telegram(readings);
  }

  awaitable<void> writer() {
    asio::steady_timer pace(io_);
    std::vector<RangeReading> readings;
    for (;;) {
      if (queue_.empty()) {
        writing_ = false;
        wake_streamer_.cancel();
        co_await wait(wake_writer_, std::chrono::hours(1));
        continue;
      }
      writing_ = true;
      DeviceOutput item = std::move(queue_.front());
      queue_.pop_front();
      if (item.action == DeviceOutput::Action::SwitchBaud) {
        std::lock_guard lock(mutex_);
        device_.set_baud(item.baud);
        continue;
      }
      if (item.action == DeviceOutput::Action::Restart) {
        co_await restart();
        continue;
      }
      const bool is_scan = item.action == DeviceOutput::Action::SendScan;
      if (is_scan) item.bytes = draw_scan(nullptr, readings);
      // Faults strike telegrams (not lone ACK / NAK bytes) that go out at the host's rate: a
      // telegram lost to a rate mismatch is not there to be damaged.
      const bool delivered = rates_match();
      LinkFault fault = LinkFault::None;
      if (item.bytes.size() > 1 && delivered) {
        std::lock_guard lock(mutex_);
        fault = injector_.apply(item.bytes);
      }
      if (fault != LinkFault::None && fault_observer) fault_observer(fault, Clock::now());
      if (is_scan) {
        SentScan sent;
        {
          std::lock_guard lock(mutex_);
          sent.sequence = counters_.scans_sent++;
          sent.twin_time_s = recording_ ? recorded_scan_time_ : twin_.time_s();
        }
        sent.readings = &readings;
        sent.units = device_.configuration().units();
        sent.fault = fault;
        if (scan_observer) scan_observer(sent);
      }
      if (fault == LinkFault::HangUp) {
        hang_up();
        continue;
      }
      if (fault == LinkFault::Reset) {
        co_await restart();
        continue;
      }
      if (fault == LinkFault::Stall) co_await wait(pace, seconds(settings_.faults.stall_s));
      if (!delivered || !rates_match()) {
        std::lock_guard lock(mutex_);
        counters_.bytes_lost_to_rate_mismatch += item.bytes.size();
        continue;
      }
      boost::system::error_code ec;
      co_await asio::async_write(master_, asio::buffer(item.bytes),
                                 asio::redirect_error(use_awaitable, ec));
      {
        std::lock_guard lock(mutex_);
        if (item.bytes.size() > 1) ++counters_.telegrams_sent;
      }
      if (settings_.time_scale > 0.0) {
        // The line carries 10 bits per byte (start, 8 data, stop).
        const double line_s = 10.0 * static_cast<double>(item.bytes.size()) / device_.baud();
        co_await wait(pace, seconds(line_s / settings_.time_scale));
      }
    }
  }

  awaitable<void> restart() {
    {
      std::lock_guard lock(mutex_);
      device_.restart();
    }
    queue_.clear();
    asio::steady_timer booting(io_);
    co_await wait(booting, seconds(settings_.restart_s));
    if (powered_) enqueue_send(device_.power_on_telegram());
  }

  // Advances the twin by one scan period; powers the device off and on with the schedule.
  void tick(double period_s) {
    bool on = false;
    {
      std::lock_guard lock(mutex_);
      twin_.advance_to(twin_.time_s() + period_s);
      on = twin_.power_on();
    }
    switch_power(on);
  }

  // Powers the device off or on (a restart, announced when on) when the state changes.
  void switch_power(bool on) {
    if (on == powered_) return;
    powered_ = on;
    queue_.clear();
    {
      std::lock_guard lock(mutex_);
      device_.restart();
    }
    if (on) enqueue_send(device_.power_on_telegram());
  }

  awaitable<void> streamer() {
    const Clock::time_point wall_start = Clock::now();
    const double twin_start = twin_.time_s();
    for (;;) {
      const double period_s =
          device_.variant().turns_per_scan() / settings_.scenario.scanner.scan_rate_hz;
      if (settings_.time_scale > 0.0) {
        const double next = twin_.time_s() + period_s;
        co_await wait(
            wake_streamer_,
            wall_start + seconds((next - twin_start) / settings_.time_scale) - Clock::now());
        if (Clock::now() < wall_start + seconds((next - twin_start) / settings_.time_scale)) {
          continue;  // woken early by a request; the tick is not due yet
        }
        tick(period_s);
        if (!device_.streaming() || !powered_) continue;
        if (idle()) {
          enqueue(DeviceOutput{DeviceOutput::Action::SendScan, {}, 0});
        } else {
          std::lock_guard lock(mutex_);
          ++counters_.scans_skipped;
        }
      } else {
        if (!powered_) {
          tick(period_s);
          continue;
        }
        // Nobody hears a line at the wrong rate: wait rather than race the twin ahead.
        if (!device_.streaming() || !idle() || !rates_match()) {
          co_await wait(wake_streamer_, std::chrono::milliseconds(20));
          continue;
        }
        tick(period_s);
        if (powered_ && device_.streaming()) {
          enqueue(DeviceOutput{DeviceOutput::Action::SendScan, {}, 0});
        }
      }
    }
  }

  // The streamer for a recording: steps the playback from event to event (scans, case
  // readings, power changes) at their recorded times, scaled; at time_scale 0 as fast as the
  // host reads, each scan held until the host streams and each event until the line is idle.
  awaitable<void> play_recording() {
    playback_origin_ = Clock::now();
    const double recording_start = recording_->time_s();
    for (;;) {
      std::optional<double> due;
      {
        std::lock_guard lock(mutex_);
        due = recording_->next_event_time();
        if (!due) counters_.playback_finished = true;
      }
      if (!due) {
        co_await wait(wake_streamer_, std::chrono::hours(1));
        continue;
      }
      if (settings_.time_scale > 0.0) {
        const auto at = playback_origin_ + seconds((*due - recording_start) / settings_.time_scale);
        if (Clock::now() < at) {
          co_await wait(wake_streamer_, at - Clock::now());
          continue;  // maybe woken early by a request
        }
      } else if (!idle()) {
        co_await wait(wake_streamer_, std::chrono::milliseconds(20));
        continue;
      }
      bool on = false;
      bool scan_due = false;
      {
        std::lock_guard lock(mutex_);
        recording_->advance_to(std::max(*due, recording_->time_s()));
        const int switched = power_switch_;
        on = switched >= 0 ? switched == 1 : recording_->power_on();
        const std::optional<double> next_scan = recording_->next_scan_time();
        scan_due = next_scan && *next_scan <= recording_->time_s();
      }
      report_played_events();
      switch_power(on);
      if (scan_due) co_await send_recorded_scan();
    }
  }

  // Hands the case readings and power changes the playback has passed, in the recording's
  // order, to the observer.
  void report_played_events() {
    std::vector<RecordingPlayback::Event> events;
    {
      std::lock_guard lock(mutex_);
      events = recording_->take_played_events();
    }
    if (!playback_observer) return;
    for (const auto& e : events) {
      playback_observer(PlaybackEvent{e.time_s, e.case_c, e.power, {}});
    }
  }

  // Takes the next recorded scan and sends it if the device streams and the line is free; at
  // time_scale 0, or holding recorded scans, it waits for both first (a hold pauses the
  // playback clock).
  awaitable<void> send_recorded_scan() {
    if (settings_.time_scale == 0.0 || settings_.hold_recorded_scans) {
      const Clock::time_point held_from = Clock::now();
      while (powered_ && !(device_.streaming() && idle() && rates_match())) {
        co_await wait(wake_streamer_, std::chrono::milliseconds(20));
      }
      playback_origin_ += Clock::now() - held_from;
    }
    {
      std::lock_guard lock(mutex_);
      const double time_s = *recording_->next_scan_time();
      std::vector<RangeReading> scan = recording_->next_scan();
      if (!powered_ || !device_.streaming()) {
        // Not sent: the device is off, or no host streams.
      } else if (idle()) {
        recorded_scan_ = std::move(scan);  // idle: the writer holds no scan it has yet to draw
        recorded_scan_time_ = time_s;
        enqueue(DeviceOutput{DeviceOutput::Action::SendScan, {}, 0});
        if (playback_observer) {
          PlaybackEvent sent{time_s, std::nullopt, std::nullopt, {}};
          for (const RangeReading& r : recorded_scan_) {
            sent.scan_ranges_mm.push_back(r.status == ReadingStatus::Valid
                                              ? r.range_mm
                                              : std::numeric_limits<double>::quiet_NaN());
          }
          playback_observer(sent);
        }
      } else {
        ++counters_.scans_skipped;
      }
    }
    report_played_events();  // those recorded after the scan at its very time
  }
};

Emulator::Emulator(EmulatorSettings settings)
    : server_(std::make_unique<Server>(std::move(settings))) {}
Emulator::~Emulator() = default;
void Emulator::on_scan_sent(ScanObserver observer) {
  server_->scan_observer = std::move(observer);
}
void Emulator::on_fault(FaultObserver observer) {
  server_->fault_observer = std::move(observer);
}
void Emulator::on_playback_event(PlaybackObserver observer) {
  server_->playback_observer = std::move(observer);
}
void Emulator::start() {
  server_->start();
}
void Emulator::stop() {
  server_->stop();
}
std::string Emulator::device_path() const {
  return server_->device_path();
}
EmulatorCounters Emulator::counters() const {
  return server_->counters();
}
double Emulator::read_case_sensor() {
  return server_->read_case_sensor();
}
double Emulator::twin_time_s() const {
  return server_->twin_time_s();
}
bool Emulator::power_on() const {
  return server_->power_on();
}
void Emulator::set_power(bool on) {
  server_->set_power(on);
}

}  // namespace tofcomp::sim::lms200
