#include "hal/lms2xx/host_driver.hpp"

#include <poll.h>
#include <termios.h>

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "hal/lms2xx/messages.hpp"

namespace tofcomp::hal::lms2xx {

namespace asio = boost::asio;
using asio::awaitable;
using asio::use_awaitable;
using Clock = std::chrono::steady_clock;

namespace {

// A silent stream's checks at the power-on rate are this many scan intervals apart.
constexpr int kListenScansBetweenChecks = 2;

// A failure of the link that ends this attempt; the supervisor starts over.
class LinkError : public core::Error {
 public:
  using core::Error::Error;
};

std::string hex(std::uint8_t byte) {
  static const char* digits = "0123456789ABCDEF";
  return std::string("0x") + digits[byte >> 4] + digits[byte & 0xf];
}

}  // namespace

// The request in flight: what answers it, and what has come so far.
struct Lms2xxDriver::Pending {
  std::uint8_t reply_code = 0;
  bool acked = false;
  std::chrono::steady_clock::time_point acked_at;
  bool naked = false;
  std::optional<Telegram> reply;
};

void DriverSettings::validate() const {
  if (device.empty()) throw core::InvalidInput("lms2xx driver: device: no serial port given");
  if (!is_supported_baud(baud)) {
    throw core::InvalidInput("lms2xx driver: baud: " + std::to_string(baud) +
                             " is none of 9600, 19200, 38400, 500000");
  }
  if (!variant.is_valid()) {
    throw core::InvalidInput("lms2xx driver: variant " + to_string(variant) +
                             " does not exist (100° or 180°; 1°, 0.5°, or 0.25° with 100° only)");
  }
  if (attempts < 1 || silence_scans < 1 || ack_timeout.count() <= 0 ||
      reply_timeout.count() <= 0 || scan_timeout.count() <= 0 || backoff_initial.count() <= 0 ||
      backoff_max < backoff_initial) {
    throw core::InvalidInput(
        "lms2xx driver: attempts, silence_scans, timeouts and backoff must be positive, "
        "backoff_max >= backoff_initial");
  }
}

std::string to_string(LinkState state) {
  switch (state) {
    case LinkState::Stopped:
      return "stopped";
    case LinkState::Connecting:
      return "connecting";
    case LinkState::Configuring:
      return "configuring";
    case LinkState::Streaming:
      return "streaming";
    case LinkState::Backoff:
      return "backoff";
  }
  return "unknown";
}

Lms2xxDriver::Lms2xxDriver(asio::io_context& io, DriverSettings settings, ScanHandler on_scan,
                           StateHandler on_state)
    : io_(io),
      settings_(std::move(settings)),
      device_(settings_.device),
      on_scan_(std::move(on_scan)),
      on_state_(std::move(on_state)),
      port_(io),
      reply_wait_(io),
      idle_timer_(io, Clock::time_point::max()),
      watch_timer_(io),
      backoff_timer_(io) {
  settings_.validate();
}

Lms2xxDriver::~Lms2xxDriver() = default;

const DriverCounters& Lms2xxDriver::counters() const {
  counters_.decoder = decoder_.counters();
  return counters_;
}

void Lms2xxDriver::start() {
  stopping_ = false;
  asio::co_spawn(io_, supervise(), asio::detached);
  asio::co_spawn(io_, idle_flusher(), asio::detached);
}

void Lms2xxDriver::stop() {
  stopping_ = true;
  close_port();
  reply_wait_.cancel();
  idle_timer_.cancel();
  watch_timer_.cancel();
  backoff_timer_.cancel();
  set_state(LinkState::Stopped, "stopped by the host");
}

void Lms2xxDriver::reconnect_now() {
  backoff_reset_ = true;
  backoff_timer_.cancel();
}

void Lms2xxDriver::set_state(LinkState state, const std::string& why) {
  state_ = state;
  if (on_state_) on_state_(state, why);
}

std::chrono::steady_clock::duration Lms2xxDriver::line_time(std::size_t bytes) const {
  return std::chrono::duration_cast<Clock::duration>(line_transfer_time(bytes, port_baud_));
}

void Lms2xxDriver::open_port() {
  boost::system::error_code ec;
  port_.open(device_, ec);
  if (ec) throw LinkError("cannot open " + device_ + ": " + ec.message());
  using base = asio::serial_port_base;
  port_.set_option(base::character_size(8), ec);
  if (!ec) port_.set_option(base::parity(base::parity::none), ec);
  if (!ec) port_.set_option(base::stop_bits(base::stop_bits::one), ec);
  if (!ec) port_.set_option(base::flow_control(base::flow_control::none), ec);
  if (ec) throw LinkError("cannot set 8N1 on " + device_ + ": " + ec.message());
  decoder_.reset();
  link_lost_ = false;
  asio::co_spawn(io_, reader(++reader_generation_), asio::detached);
}

// The port failed (a hang-up, the device gone). Whichever sees it first reports it: the reader
// (a read fails), a request (its write fails) or a rate change (tcsetattr fails with EIO). Which
// one that is comes down to scheduling: a hang-up that lands after the reader's last read and
// before the next request's write fails that write at once, while the reader would learn of it
// only at the next poll of the port, after the driver has given up on the port and closed it.
// Counted once per port opened, whichever of them saw it.
void Lms2xxDriver::lose_link() {
  if (!link_lost_) ++counters_.link_losses;
  link_lost_ = true;
  reply_wait_.cancel();
  watch_timer_.cancel();
}

// Whether the open port's line has hung up, asked of the port itself (poll's POLLHUP), not of
// the reader: a hang-up in the instant before the driver closes the port for another reason (a
// bring-up timing out just then) leaves the reader's failed read queued, and a reader replaced
// by the close never reports it.
bool Lms2xxDriver::port_hung_up() {
  pollfd fd{port_.native_handle(), POLLIN, 0};
  return ::poll(&fd, 1, 0) > 0 && (fd.revents & (POLLHUP | POLLERR)) != 0;
}

void Lms2xxDriver::close_port() {
  ++reader_generation_;
  boost::system::error_code ignored;
  // A hang-up the reader had not been told of when the port closes is a link loss all the same
  // (once per port, as lose_link counts it).
  if (port_.is_open() && !link_lost_ && port_hung_up()) {
    ++counters_.link_losses;
    link_lost_ = true;
  }
  if (port_.is_open()) {
    port_.cancel(ignored);
    port_.close(ignored);
  }
}

void Lms2xxDriver::set_port_baud(unsigned baud) {
  boost::system::error_code ec;
  port_.set_option(asio::serial_port_base::baud_rate(baud), ec);
  if (ec) {
    // EIO is a hung-up line (every call on it fails so); another error is a rate this port
    // cannot take, a fault of the settings, not of the link.
    if (ec == boost::system::errc::io_error) lose_link();
    throw LinkError("cannot set " + std::to_string(baud) + " Bd on " + device_ + ": " +
                    ec.message());
  }
  port_baud_ = baud;
  // Bytes received at the old rate mean nothing at the new one, but a late answer to a request
  // made at the old rate would be taken for the answer to the next request at this one (a rate
  // search then "finds" the device at a rate it is not at). Those still in the kernel's buffer
  // are flushed; those a read has already taken go with the reader, which starts anew.
  ::tcflush(port_.native_handle(), TCIFLUSH);
  ++reader_generation_;
  port_.cancel(ec);
  asio::co_spawn(io_, reader(reader_generation_), asio::detached);
  decoder_.reset();
}

awaitable<void> Lms2xxDriver::sleep(Clock::duration d) {
  asio::steady_timer timer(io_, d);
  boost::system::error_code ec;
  co_await timer.async_wait(asio::redirect_error(use_awaitable, ec));
}

awaitable<void> Lms2xxDriver::supervise() {
  auto backoff = settings_.backoff_initial;
  bool port_usable = false;
  while (!stopping_) {
    std::string why;
    // Whether the device answers is learnt afresh at each attempt: a port that no longer
    // opens backs off however well the device answered before.
    device_answered_ = false;
    try {
      if (!port_usable) {
        device_ = settings_.current_device ? settings_.current_device() : settings_.device;
        set_state(LinkState::Connecting, "opening " + device_);
        close_port();
        open_port();
        port_usable = true;
      }
      set_state(LinkState::Configuring, "bringing the device up");
      co_await bring_up();
      backoff = settings_.backoff_initial;
      ++counters_.bring_ups;
      set_state(LinkState::Streaming, "streaming at " + std::to_string(port_baud_) + " Bd");
      why = co_await watch_stream();
      if (link_lost_) port_usable = false;
      if (stopping_) break;
      set_state(LinkState::Configuring, why);
      continue;  // a lost stream is re-established at once
    } catch (const LinkError& e) {
      why = e.what();
    }
    if (stopping_) break;
    close_port();
    port_usable = false;
    // Backing off is for a device that does not answer: one that answered and then failed
    // (a damaged reply, a reset in the middle) is tried again after the shortest wait.
    if (device_answered_) backoff = settings_.backoff_initial;
    if (backoff_reset_) backoff = settings_.backoff_initial;
    backoff_reset_ = false;
    set_state(LinkState::Backoff, why);
    backoff_timer_.expires_after(backoff);
    boost::system::error_code ignored;
    co_await backoff_timer_.async_wait(asio::redirect_error(use_awaitable, ignored));
    backoff =
        backoff_reset_ ? settings_.backoff_initial : std::min(backoff * 2, settings_.backoff_max);
    backoff_reset_ = false;
  }
}

awaitable<void> Lms2xxDriver::reader(std::uint64_t generation) {
  std::vector<std::uint8_t> buffer(4096);
  for (;;) {
    // A reader replaced before it started (or between reads) leaves the bytes to its successor.
    if (generation != reader_generation_) co_return;
    boost::system::error_code ec;
    const std::size_t n = co_await port_.async_read_some(asio::buffer(buffer),
                                                         asio::redirect_error(use_awaitable, ec));
    if (generation != reader_generation_) co_return;
    if (ec) {
      lose_link();
      co_return;
    }
    const auto now = Clock::now();
    const auto now_wall = std::chrono::system_clock::now();
    last_byte_ = now;
    last_byte_wall_ = now_wall;
    decoder_.feed(std::span(buffer.data(), n),
                  [&](const DecoderEvent& e) { dispatch(e, now, now_wall); });
    // A frame left incomplete is truncated if the line stays quiet this long.
    idle_timer_.expires_at(decoder_.pending_bytes() > 0
                               ? now + std::chrono::milliseconds(20) + line_time(32)
                               : Clock::time_point::max());
  }
}

awaitable<void> Lms2xxDriver::idle_flusher() {
  while (!stopping_) {
    boost::system::error_code ec;
    co_await idle_timer_.async_wait(asio::redirect_error(use_awaitable, ec));
    if (stopping_) co_return;
    if (ec) continue;  // re-armed by the reader
    idle_timer_.expires_at(Clock::time_point::max());
    const auto now = Clock::now();
    // The bytes of what the flush finds arrived with the last read, not now.
    decoder_.flush_idle([&](const DecoderEvent& e) { dispatch(e, now, last_byte_wall_); });
  }
}

void Lms2xxDriver::dispatch(const DecoderEvent& event, Clock::time_point when,
                            std::chrono::system_clock::time_point when_wall) {
  device_answered_ = true;
  if (event.kind != DecoderEvent::Kind::Telegram) {
    if (pending_) {
      (event.kind == DecoderEvent::Kind::Ack ? pending_->acked : pending_->naked) = true;
      pending_->acked_at = when;
      reply_wait_.cancel();
    }
    return;
  }
  const Telegram& t = *event.telegram;
  if (t.command == kPowerOnReply) {
    ++counters_.device_resets;
    device_reset_seen_ = true;
    watch_timer_.cancel();
    reply_wait_.cancel();
    return;
  }
  if (pending_ && t.command == pending_->reply_code && t.command != kScanReply) {
    pending_->reply = t;
    reply_wait_.cancel();
    return;
  }
  if (t.command != kScanReply || !accepting_scans_) return;
  HostScan scan;
  try {
    scan.scan = decode_scan_data(t.data, settings_.measuring_mode);
  } catch (const core::InvalidInput&) {
    ++counters_.rejected_scans;
    return;
  }
  if (scan.scan.distance_codes.size() !=
          static_cast<std::size_t>(settings_.variant.values_per_scan()) ||
      scan.scan.units != settings_.units) {
    ++counters_.rejected_scans;
    return;
  }
  scan.sequence = counters_.scans++;
  scan.received = when;
  scan.received_wall = when_wall;
  scan.rays = estimate_ray_timing(when_wall, t.data.size() + kFrameOverheadBytes, port_baud_,
                                  settings_.variant);
  scan.measuring_mode = settings_.measuring_mode;
  last_scan_ = when;
  if (on_scan_) on_scan_(scan);
}

awaitable<bool> Lms2xxDriver::exchange_once(const Telegram& request, Telegram& reply,
                                            OnRestart on_restart) {
  pending_ = std::make_unique<Pending>();
  pending_->reply_code = static_cast<std::uint8_t>(request.command | kReplyFlag);
  const auto bytes = encode_telegram(request);
  decoder_.expect_ack();
  boost::system::error_code ec;
  co_await asio::async_write(port_, asio::buffer(bytes), asio::redirect_error(use_awaitable, ec));
  if (ec) {
    lose_link();
    pending_.reset();
    throw LinkError("writing to " + device_ + " failed: " + ec.message());
  }
  // A streamed scan may be on the line ahead of the answer: while bytes keep arriving, the wait
  // stretches by up to one longest telegram's line time. A silent line fails fast, so a search
  // for the device's rate does not wait out the line time of 9600 Bd at every wrong rate.
  const auto sent = Clock::now();
  const std::uint64_t resets_before = counters_.device_resets;
  const auto in_flight = line_time(kMaxPayloadBytes + kFrameOverheadBytes + bytes.size());
  const auto stretched = [&](Clock::time_point base, Clock::duration wait) {
    const bool line_busy = last_byte_ > sent;
    return line_busy ? std::min(base + wait + in_flight, last_byte_ + wait) : base + wait;
  };
  for (;;) {
    if (link_lost_ || stopping_) {
      pending_.reset();
      throw LinkError(stopping_ ? "stopped" : "the link to " + device_ + " was lost");
    }
    if (pending_->reply) {
      reply = *pending_->reply;
      pending_.reset();
      co_return true;
    }
    if (pending_->naked) {
      ++counters_.naks;
      pending_.reset();
      co_return false;
    }
    // Checking a silent stream for a restart, a device that announces its restart since the
    // request went out booted through it and never heard it. (At a bring-up a device's power-on
    // telegram may precede its answer: the host opened the port as the device came up.)
    if (on_restart == OnRestart::GiveUp && counters_.device_resets != resets_before &&
        !pending_->acked) {
      pending_.reset();
      co_return false;
    }
    const auto deadline = pending_->acked ? stretched(pending_->acked_at, settings_.reply_timeout)
                                          : stretched(sent, settings_.ack_timeout);
    if (Clock::now() >= deadline) {
      ++counters_.timeouts;
      pending_.reset();
      co_return false;
    }
    reply_wait_.expires_at(deadline);
    co_await reply_wait_.async_wait(asio::redirect_error(use_awaitable, ec));
  }
}

awaitable<Telegram> Lms2xxDriver::transact(const Telegram& request, int attempts) {
  Telegram reply;
  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (co_await exchange_once(request, reply)) co_return reply;
  }
  throw LinkError("request " + hex(request.command) + " got no answer in " +
                  std::to_string(attempts) + " attempts at " + std::to_string(port_baud_) + " Bd");
}

// Asks for the variant the host wants (a request the bring-up makes anyway): its reply is a
// dozen bytes where the status reply is some 150, a sixth of a second at 9600 Bd.
awaitable<bool> Lms2xxDriver::probe(unsigned baud, OnRestart on_restart) {
  set_port_baud(baud);
  Telegram reply;
  if (!co_await exchange_once(variant_request(settings_.variant), reply, on_restart)) {
    co_return false;
  }
  try {
    static_cast<void>(parse_variant_reply(reply));
  } catch (const core::InvalidInput&) {
    co_return false;
  }
  co_return true;
}

awaitable<unsigned> Lms2xxDriver::find_rate() {
  // The rate the device was last seen at first (a dropped line leaves it there), then the
  // power-on rate, the configured one, and the rest.
  if (restarted_device_answered_) {  // the silent stream's check found it there just now
    restarted_device_answered_ = false;
    device_reset_seen_ = false;
    last_device_baud_ = kPowerOnBaud;
    co_return kPowerOnBaud;
  }
  std::vector<unsigned> order;
  const auto add = [&order](unsigned b) {
    if (std::find(order.begin(), order.end(), b) == order.end()) order.push_back(b);
  };
  if (device_reset_seen_) add(kPowerOnBaud);  // it announced its restart: at its power-on rate
  if (last_device_baud_) add(*last_device_baud_);
  add(kPowerOnBaud);
  add(settings_.baud);
  for (const unsigned b : kSupportedBauds) add(b);
  for (int round = 0; round < 2; ++round) {
    for (const unsigned baud : order) {
      if (co_await probe(baud)) {
        if (baud != order.front()) ++counters_.rate_searches;
        if (last_device_baud_ && *last_device_baud_ != kPowerOnBaud && baud == kPowerOnBaud &&
            !device_reset_seen_) {
          ++counters_.device_resets;  // found at the power-on rate: it restarted unseen
        }
        device_reset_seen_ = false;
        last_device_baud_ = baud;
        co_return baud;
      }
    }
  }
  throw LinkError("no answer from " + device_ + " at any rate");
}

awaitable<void> Lms2xxDriver::bring_up() {
  const int n = settings_.attempts;
  accepting_scans_ = false;
  const unsigned found = co_await find_rate();
  if (found != settings_.baud) {
    const Telegram reply =
        co_await transact(switch_mode_request(*mode_for_baud(settings_.baud)), n);
    if (parse_mode_switch_reply(reply) != ModeSwitchResult::Success) {
      throw LinkError("the device refused to switch to " + std::to_string(settings_.baud) + " Bd");
    }
    last_device_baud_ = settings_.baud;
    set_port_baud(settings_.baud);
  }
  const VariantReply variant =
      parse_variant_reply(co_await transact(variant_request(settings_.variant), n));
  if (!variant.accepted || !(variant.active == settings_.variant)) {
    throw LinkError("the device refused the variant " + to_string(settings_.variant));
  }
  ConfigurationBlock block =
      parse_configuration_reply(co_await transact(configuration_request(), n));
  if (block.units() != settings_.units || block.measuring_mode() != settings_.measuring_mode) {
    if (parse_mode_switch_reply(co_await transact(installation_mode_request(), n)) !=
        ModeSwitchResult::Success) {
      throw LinkError("the device refused installation mode (password)");
    }
    block.set_units(settings_.units);
    block.set_measuring_mode(settings_.measuring_mode);
    const ConfigureReply stored =
        parse_configure_reply(co_await transact(configure_request(block), n));
    if (!stored.accepted || !(stored.stored == block)) {
      throw LinkError("the device refused the configuration (units " + to_string(settings_.units) +
                      ")");
    }
  }
  // Scans may follow the reply in the same read: from here on they have the shape asked for.
  accepting_scans_ = true;
  last_scan_ = Clock::now();
  if (parse_mode_switch_reply(co_await transact(switch_mode_request(OperatingMode::ContinuousAll),
                                                n)) != ModeSwitchResult::Success) {
    throw LinkError("the device refused continuous output");
  }
}

// The time between scans at the configured variant and rate: the mirror's turns a scan takes,
// or the scan telegram's line time where the line is the slower.
Clock::duration Lms2xxDriver::scan_interval() const {
  const auto turns = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
      settings_.variant.turns_per_scan() / kMirrorTurnsPerSecond));
  const std::size_t telegram_bytes =
      kFrameOverheadBytes + scan_data_bytes(settings_.variant.values_per_scan());
  return std::max(turns, std::chrono::duration_cast<Clock::duration>(
                             line_transfer_time(telegram_bytes, settings_.baud)));
}

// Whether a device that fell silent restarted: a restart (a brown-out, a watchdog) brings it
// back at its power-on rate with continuous output off, and its power-on telegram at that rate
// never reaches a host at another. One request at 9600 Bd finds it there in a few tens of
// milliseconds, where waiting out scan_timeout costs a second of scans. A device that does not
// answer there (stalled, or still restarting) is listened to again at the running rate.
awaitable<bool> Lms2xxDriver::restarted_device_answers() {
  ++counters_.restart_checks;
  const bool answered = co_await probe(kPowerOnBaud, OnRestart::GiveUp);
  // Found when it answers, or when its power-on telegram came while the port listened there
  // (it restarted after the request was sent, and never heard it).
  if (answered || device_reset_seen_) {
    if (!device_reset_seen_) ++counters_.device_resets;  // its power-on telegram not heard
    restarted_device_answered_ = true;
    co_return true;
  }
  if (!link_lost_ && !stopping_) set_port_baud(settings_.baud);
  co_return false;
}

awaitable<std::string> Lms2xxDriver::watch_stream() {
  const bool may_restart_unheard = settings_.baud != kPowerOnBaud;
  const Clock::duration first_check = settings_.silence_scans * scan_interval();
  // Between checks, the port listens at the running rate for this long: a stalled stream that
  // resumes is heard there, and a scan lost to a check costs at most one check's wait.
  const Clock::duration between_checks = kListenScansBetweenChecks * scan_interval();
  Clock::duration check_after = first_check;
  Clock::time_point silent_since = last_scan_;
  for (;;) {
    if (stopping_) co_return "stopped";
    if (link_lost_) co_return "the link to " + device_ + " was lost";
    if (device_reset_seen_) co_return "the device restarted";
    if (last_scan_ > silent_since) {  // scans again: the next silence is checked from its start
      silent_since = last_scan_;
      check_after = first_check;
    }
    const auto silent_until = last_scan_ + settings_.scan_timeout;
    const auto now = Clock::now();
    if (now >= silent_until) {
      ++counters_.stream_timeouts;
      co_return "no scan for " + std::to_string(settings_.scan_timeout.count()) + " ms";
    }
    const auto check_at = silent_since + check_after;
    if (may_restart_unheard && now >= check_at) {
      if (co_await restarted_device_answers()) {
        co_return "no scan for " +
            std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                               Clock::now() - last_scan_).count()) +
            " ms and the device answered at " + std::to_string(kPowerOnBaud) +
            " Bd: it restarted";
      }
      silent_since = Clock::now();  // the next check after listening here between_checks
      check_after = between_checks;
      continue;
    }
    watch_timer_.expires_at(may_restart_unheard ? std::min(silent_until, check_at) : silent_until);
    boost::system::error_code ec;
    co_await watch_timer_.async_wait(asio::redirect_error(use_awaitable, ec));
  }
}

}  // namespace tofcomp::hal::lms2xx
