#include "sim/lms200/pty_link.hpp"

#include <filesystem>

#include "core/error.hpp"
#include "hal/lms2xx/scan_timing.hpp"

namespace tofcomp::sim::lms200 {

namespace asio = boost::asio;
using asio::awaitable;
using asio::use_awaitable;

PtyLink::PtyLink(EmulatorSettings settings, std::unique_ptr<ScanSource> source)
    : settings_(std::move(settings)),
      source_(std::move(source)),
      device_(settings_.identity),
      injector_(settings_.faults, settings_.fault_seed) {
  if (settings_.time_scale < 0.0) {
    throw core::InvalidInput(
        "emulator: time_scale must be 0 (as fast as the host reads) or positive, not " +
        std::to_string(settings_.time_scale));
  }
}

PtyLink::~PtyLink() {
  stop();
}

void PtyLink::start() {
  open_pty();
  powered_ = source_->power_on();
  if (powered_) enqueue_send(device_.power_on_telegram());
  asio::co_spawn(io_, reader(generation_), failure_reporter("reader"));
  asio::co_spawn(io_, writer(), failure_reporter("writer"));
  asio::co_spawn(io_, source_->stream(*this), failure_reporter("streamer"));
  thread_ = std::thread([this] { io_.run(); });
}

void PtyLink::stop() {
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

std::string PtyLink::device_path() const {
  std::lock_guard lock(mutex_);
  return settings_.link.empty() ? (pty_ ? pty_->slave_path() : std::string())
                                : settings_.link.string();
}

EmulatorCounters PtyLink::counters() const {
  std::lock_guard lock(mutex_);
  EmulatorCounters c = counters_;
  c.injected = injector_.injected();
  c.requests = device_.decoder_counters().telegrams;
  c.naks_sent = device_.naks_sent();
  return c;
}

double PtyLink::read_case_sensor() {
  std::lock_guard lock(mutex_);
  return source_->read_case_sensor();
}

double PtyLink::source_time_s() const {
  std::lock_guard lock(mutex_);
  return source_->time_s();
}

std::optional<bool> PtyLink::switched_power() const {
  const int switched = power_switch_;
  if (switched < 0) return std::nullopt;
  return switched == 1;
}

bool PtyLink::power_on() const {
  return switched_power().value_or(powered_.load());
}

void PtyLink::set_power(bool on) {
  power_switch_ = on ? 1 : 0;
  asio::post(io_, [this, on] {
    {
      std::lock_guard lock(mutex_);
      source_->override_power(on);
    }
    switch_power(on);
  });
}

bool PtyLink::rates_match() const {
  return pty_->host_baud() == device_.baud();
}

void PtyLink::switch_power(bool on) {
  if (on == powered_) return;
  powered_ = on;
  queue_.clear();
  {
    std::lock_guard lock(mutex_);
    device_.restart();
  }
  if (on) enqueue_send(device_.power_on_telegram());
}

void PtyLink::queue_scan() {
  enqueue(DeviceOutput{DeviceOutput::Action::SendScan, {}, 0});
}

void PtyLink::count_skipped_scan() {
  std::lock_guard lock(mutex_);
  ++counters_.scans_skipped;
}

void PtyLink::mark_playback_finished() {
  std::lock_guard lock(mutex_);
  counters_.playback_finished = true;
}

awaitable<void> PtyLink::wait_for_host(Clock::duration d) {
  co_await wait(wake_source_, d);
}

void PtyLink::open_pty() {
  auto pty = std::make_unique<PtyPort>();
  if (!settings_.link.empty()) publish_symlink(settings_.link, pty->slave_path());
  if (master_.is_open()) static_cast<void>(master_.release());
  master_.assign(pty->master_fd());
  std::lock_guard lock(mutex_);
  pty_ = std::move(pty);
}

void PtyLink::hang_up() {
  ++generation_;
  boost::system::error_code ignored;
  master_.cancel(ignored);
  static_cast<void>(master_.release());
  pty_->close();
  queue_.clear();
  open_pty();
  asio::co_spawn(io_, reader(generation_), failure_reporter("reader"));
}

// A coroutine that ends with an exception stops the device: the error is kept for counters()
// and the io_context stops, so a failure is never silent.
std::function<void(std::exception_ptr)> PtyLink::failure_reporter(const char* part) {
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

void PtyLink::enqueue(DeviceOutput output) {
  queue_.push_back(std::move(output));
  wake_writer_.cancel();
}

void PtyLink::enqueue_send(std::vector<std::uint8_t> bytes) {
  enqueue(DeviceOutput{DeviceOutput::Action::Send, std::move(bytes), 0});
}

awaitable<void> PtyLink::wait(asio::steady_timer& timer, Clock::duration d) {
  timer.expires_after(d);
  boost::system::error_code ec;
  co_await timer.async_wait(asio::redirect_error(use_awaitable, ec));
}

awaitable<void> PtyLink::reader(std::uint64_t generation) {
  std::vector<std::uint8_t> buffer(4096);
  std::vector<DeviceOutput> outputs;
  for (;;) {
    boost::system::error_code ec;
    const std::size_t n = co_await master_.async_read_some(asio::buffer(buffer),
                                                           asio::redirect_error(use_awaitable, ec));
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
    if (restarting_) {
      std::lock_guard lock(mutex_);
      counters_.bytes_unheard_while_restarting += n;
      continue;
    }
    outputs.clear();
    {
      std::lock_guard lock(mutex_);
      device_.receive(std::span(buffer.data(), n), outputs);
    }
    for (auto& o : outputs) enqueue(std::move(o));
    wake_source_.cancel();
  }
}

std::vector<std::uint8_t> PtyLink::draw_scan(std::vector<RangeReading>& readings, double& time_s) {
  std::lock_guard lock(mutex_);
  DrawnScan scan = source_->draw_scan(device_);
  readings = std::move(scan.readings);
  time_s = scan.time_s;
  return device_.scan_telegram(readings);
}

awaitable<void> PtyLink::writer() {
  asio::steady_timer pace(io_);
  std::vector<RangeReading> readings;
  double scan_time_s = 0.0;
  for (;;) {
    if (queue_.empty()) {
      writing_ = false;
      wake_source_.cancel();
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
    if (is_scan) item.bytes = draw_scan(readings, scan_time_s);
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
      sent.first_ray =
          std::chrono::system_clock::now() - hal::lms2xx::scan_sweep_duration(device_.variant());
      {
        std::lock_guard lock(mutex_);
        sent.sequence = counters_.scans_sent++;
      }
      sent.twin_time_s = scan_time_s;
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
    if (fault == LinkFault::Stall) co_await wait(pace, wall_duration(settings_.faults.stall_s));
    if (!delivered || !rates_match()) {
      std::lock_guard lock(mutex_);
      counters_.bytes_lost_to_rate_mismatch += item.bytes.size();
      continue;
    }
    co_await send_on_line(item.bytes, is_scan, pace);
    {
      std::lock_guard lock(mutex_);
      if (item.bytes.size() > 1) ++counters_.telegrams_sent;
    }
  }
}

awaitable<void> PtyLink::send_on_line(const std::vector<std::uint8_t>& bytes, bool is_scan,
                                      asio::steady_timer& pace) {
  boost::system::error_code ec;
  if (settings_.time_scale <= 0.0) {
    co_await asio::async_write(master_, asio::buffer(bytes),
                               asio::redirect_error(use_awaitable, ec));
    co_return;
  }
  // The line carries 10 bits a byte: a telegram occupies it for its line time.
  const auto line_time = wall_duration(
      std::chrono::duration<double>(hal::lms2xx::line_transfer_time(bytes.size(), device_.baud()))
          .count() /
      settings_.time_scale);
  if (is_scan) {
    // A scan reaches the host, as over a real line, once its last byte has gone out, which is
    // what the host's estimate of its rays' time counts back from (hal/lms2xx/scan_timing.hpp).
    // It goes to the pty whole then: paced byte by byte, a pause of the emulator's thread on a
    // busy machine would open a gap inside the telegram that the host rightly takes for a
    // truncation, and a real line never pauses mid-telegram.
    co_await wait(pace, line_time);
    co_await asio::async_write(master_, asio::buffer(bytes),
                               asio::redirect_error(use_awaitable, ec));
    co_return;
  }
  // Answers go out at once and hold the line for their time after: the request/answer timing
  // the host driver's timeouts are built on.
  co_await asio::async_write(master_, asio::buffer(bytes), asio::redirect_error(use_awaitable, ec));
  // The host has the whole answer now, as it would once its last byte had crossed the line: a
  // rate switch it announced takes effect now, so that the host's next request at the new rate
  // is heard (not lost to a device still holding the old rate for the answer's line time).
  if (!queue_.empty() && queue_.front().action == DeviceOutput::Action::SwitchBaud) {
    const unsigned baud = queue_.front().baud;
    queue_.pop_front();
    std::lock_guard lock(mutex_);
    device_.set_baud(baud);
  }
  co_await wait(pace, line_time);
}

awaitable<void> PtyLink::restart() {
  {
    std::lock_guard lock(mutex_);
    device_.restart();
  }
  queue_.clear();
  // Booting, the device hears nothing: a request in this time gets no answer, and the power-on
  // telegram is the first thing it sends.
  restarting_ = true;
  asio::steady_timer booting(io_);
  co_await wait(booting, wall_duration(settings_.restart_s));
  restarting_ = false;
  if (powered_) enqueue_send(device_.power_on_telegram());
}

}  // namespace tofcomp::sim::lms200
