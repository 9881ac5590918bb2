// The host side of the LMS 2xx link on Boost.Asio's serial_port: asynchronous throughout (no
// thread of its own, no busy waiting), a timeout on every request. It opens the port at the
// device's power-on rate, finds the rate when the device is already at another, switches to the
// configured rate, sets the variant, the measuring mode and the units, starts continuous output
// and delivers each scan with host timestamps. When the link drops, the device resets or the
// stream stops, it starts over, with exponential backoff between failed attempts.
#pragma once

#include <boost/asio.hpp>
#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/measuring_mode.hpp"
#include "hal/lms2xx/scan_telegram.hpp"
#include "hal/lms2xx/scan_timing.hpp"
#include "hal/lms2xx/telegram_decoder.hpp"

namespace tofcomp::hal::lms2xx {

struct DriverSettings {
  std::string device;      // the serial port, e.g. /dev/ttyUSB0 or the emulator's pty
  // When set, asked for the device's path at each opening instead of `device`: an emulated
  // LMS 200's pty, which each hang-up replaces with a new one.
  std::function<std::string()> current_device;
  unsigned baud = 500000;  // the rate to run at: 9600, 19200, 38400 or 500000
  Variant variant{180, 50};
  Units units = Units::Millimetre;
  MeasuringMode measuring_mode = MeasuringMode::Range8m;
  // Waits for the ACK and the reply; the line time of the longest telegram at the current rate
  // is added to each, since a streamed scan may be on the line ahead of the answer.
  std::chrono::milliseconds ack_timeout{60};
  std::chrono::milliseconds reply_timeout{200};
  int attempts = 3;                              // per request, before the link is started over
  std::chrono::milliseconds scan_timeout{1000};  // streaming with no scan this long: start over
  // Streaming with no scan for this many scan intervals: the device is asked, at its power-on
  // rate, whether it restarted (a restarted device talks at 9600 Bd, which a host at another rate
  // does not hear); asked again every two scan intervals while the silence lasts.
  int silence_scans = 3;
  std::chrono::milliseconds backoff_initial{50};
  std::chrono::milliseconds backoff_max{2000};

  void validate() const;  // throws core::InvalidInput naming the setting at fault
};

enum class LinkState { Stopped, Connecting, Configuring, Streaming, Backoff };
std::string to_string(LinkState state);

struct DriverCounters {
  DecoderCounters decoder;
  std::uint64_t scans = 0;           // scans delivered
  std::uint64_t rejected_scans = 0;  // 0xB0 telegrams with a good CRC but the wrong shape
  std::uint64_t naks = 0;
  std::uint64_t timeouts = 0;         // requests that got no ACK or no reply in time
  std::uint64_t link_losses = 0;      // the port failed (hang-up, device gone)
  std::uint64_t stream_timeouts = 0;  // streaming stopped without a word
  std::uint64_t device_resets = 0;    // power-on telegrams seen, or the device found at 9600
  std::uint64_t restart_checks = 0;   // silent streams checked at the power-on rate
  std::uint64_t bring_ups = 0;        // completed start-ups, the first included
  std::uint64_t rate_searches = 0;    // times the device was not at the rate first tried
};

struct HostScan {
  std::uint64_t sequence = 0;                      // counts delivered scans from 0
  std::chrono::steady_clock::time_point received;  // when its last byte was read
  std::chrono::system_clock::time_point received_wall;  // the same on the wall clock
  core::RayTiming rays;  // when its rays were measured, estimated back from received_wall
  ScanTelegram scan;
  MeasuringMode measuring_mode = MeasuringMode::Range8m;
};

class Lms2xxDriver {
 public:
  using ScanHandler = std::function<void(const HostScan&)>;
  using StateHandler = std::function<void(LinkState, const std::string& why)>;

  // Throws core::InvalidInput for bad settings. Handlers run on the io_context's thread.
  Lms2xxDriver(boost::asio::io_context& io, DriverSettings settings, ScanHandler on_scan,
               StateHandler on_state = {});
  ~Lms2xxDriver();
  Lms2xxDriver(const Lms2xxDriver&) = delete;
  Lms2xxDriver& operator=(const Lms2xxDriver&) = delete;

  void start();
  // Ends every operation; the driver can be destroyed once the io_context has run the
  // cancellations (or has stopped).
  void stop();

  // The device was just powered (its host switched the supply on): a wait between failed
  // bring-ups ends now, and the backoff starts again from its shortest, since the failures
  // while it was off were no fault of the link.
  void reconnect_now();

  LinkState state() const { return state_; }
  const DriverCounters& counters() const;
  const DriverSettings& settings() const { return settings_; }

 private:
  struct Pending;
  boost::asio::io_context& io_;
  DriverSettings settings_;
  std::string device_;  // the path of the port opened last (settings_.current_device's answer)
  ScanHandler on_scan_;
  StateHandler on_state_;
  boost::asio::serial_port port_;
  boost::asio::steady_timer reply_wait_;
  boost::asio::steady_timer idle_timer_;
  boost::asio::steady_timer watch_timer_;
  boost::asio::steady_timer backoff_timer_;
  TelegramDecoder decoder_{Sender::Device};
  mutable DriverCounters counters_;
  LinkState state_ = LinkState::Stopped;
  unsigned port_baud_ = kPowerOnBaud;
  std::optional<unsigned> last_device_baud_;
  std::unique_ptr<Pending> pending_;
  bool stopping_ = false;
  bool backoff_reset_ = false;  // reconnect_now() was called
  bool link_lost_ = false;
  bool device_reset_seen_ = false;
  bool restarted_device_answered_ = false;  // a silent stream's check found it at 9600 Bd
  bool device_answered_ = false;  // a telegram, ACK or NAK since the last bring-up began
  bool accepting_scans_ = false;  // variant and units confirmed in this bring-up
  std::uint64_t reader_generation_ = 0;
  std::chrono::steady_clock::time_point last_scan_;
  std::chrono::steady_clock::time_point last_byte_;  // when the reader last got bytes
  std::chrono::system_clock::time_point last_byte_wall_;  // the same on the wall clock

  boost::asio::awaitable<void> supervise();
  boost::asio::awaitable<void> reader(std::uint64_t generation);
  boost::asio::awaitable<void> idle_flusher();
  boost::asio::awaitable<void> bring_up();
  boost::asio::awaitable<unsigned> find_rate();
  // A request given up when the device announces a restart (a silent stream's check: a device
  // that booted through the request never heard it).
  enum class OnRestart { KeepWaiting, GiveUp };
  boost::asio::awaitable<bool> probe(unsigned baud, OnRestart on_restart = OnRestart::KeepWaiting);
  boost::asio::awaitable<Telegram> transact(const Telegram& request, int attempts);
  boost::asio::awaitable<bool> exchange_once(const Telegram& request, Telegram& reply,
                                             OnRestart on_restart = OnRestart::KeepWaiting);
  boost::asio::awaitable<std::string> watch_stream();
  boost::asio::awaitable<bool> restarted_device_answers();
  std::chrono::steady_clock::duration scan_interval() const;
  boost::asio::awaitable<void> sleep(std::chrono::steady_clock::duration d);

  void open_port();
  void close_port();
  void lose_link();
  bool port_hung_up();
  void set_port_baud(unsigned baud);
  void set_state(LinkState state, const std::string& why);
  void dispatch(const DecoderEvent& event, std::chrono::steady_clock::time_point when,
                std::chrono::system_clock::time_point when_wall);
  std::chrono::steady_clock::duration line_time(std::size_t bytes) const;
};

}  // namespace tofcomp::hal::lms2xx
