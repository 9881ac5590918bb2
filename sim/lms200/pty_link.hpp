// The emulated LMS 200's serial link on a pseudo-terminal: the device model (device.hpp)
// answering a host over a real pty, the link's rate honoured (bytes at a rate other than the
// host's are lost, as on a real line), faults injected at configured rates (a hang-up reopens
// the pty), restarts and the scanner's supply. The scans it sends come from a ScanSource (the
// twin's or a recording's), whose pacing runs on the link's thread. Used inside sim/ only: the
// programs take it as an Emulator (emulator.hpp).
#pragma once

#include <atomic>
#include <boost/asio.hpp>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "sim/lms200/device.hpp"
#include "sim/lms200/emulator.hpp"
#include "sim/lms200/fault_injector.hpp"
#include "sim/lms200/pty_port.hpp"
#include "sim/lms200/scan_source.hpp"

namespace tofcomp::sim::lms200 {

class PtyLink {
 public:
  using Clock = std::chrono::steady_clock;

  // Throws core::InvalidInput for bad fault rates or a negative time scale.
  PtyLink(EmulatorSettings settings, std::unique_ptr<ScanSource> source);
  ~PtyLink();
  PtyLink(const PtyLink&) = delete;
  PtyLink& operator=(const PtyLink&) = delete;

  // Observers run on the link's thread; set them before start().
  Emulator::ScanObserver scan_observer;
  Emulator::FaultObserver fault_observer;

  // Opens the pty and starts serving. Throws core::Error when the pty cannot be opened.
  void start();
  void stop();

  // What Emulator offers, thread-safe (emulator.hpp).
  std::string device_path() const;
  EmulatorCounters counters() const;
  double read_case_sensor();
  double source_time_s() const;
  bool power_on() const;
  void set_power(bool on);

  // For the scan source, on the link's thread.
  // Guards the source's state, the device and the counters against other threads.
  std::mutex& state_mutex() const { return mutex_; }
  const Lms200Device& device() const { return device_; }
  bool powered() const { return powered_; }
  // The supply as set_power() switched it; nullopt when it never was.
  std::optional<bool> switched_power() const;
  // Whether the host reads at the device's rate.
  bool rates_match() const;
  // Nothing queued and nothing being written.
  bool idle() const { return queue_.empty() && !writing_; }
  // Powers the device off or on (a restart, announced when on) when the state changes.
  void switch_power(bool on);
  // Queues a scan, drawn from the source when the writer sends it.
  void queue_scan();
  void count_skipped_scan();  // a scan the line could not carry
  void mark_playback_finished();
  // Waits `d`, or less when a host request arrives or the line falls idle.
  boost::asio::awaitable<void> wait_for_host(Clock::duration d);

 private:
  EmulatorSettings settings_;
  mutable std::mutex mutex_;
  std::unique_ptr<ScanSource> source_;  // outlives the io_context and the coroutines on it
  Lms200Device device_;
  FaultInjector injector_;
  EmulatorCounters counters_;
  boost::asio::io_context io_;
  std::thread thread_;
  std::unique_ptr<PtyPort> pty_;
  boost::asio::posix::stream_descriptor master_{io_};
  std::uint64_t generation_ = 0;  // bumped on each hang-up: the old reader ends
  std::deque<DeviceOutput> queue_;
  bool writing_ = false;
  std::atomic<bool> powered_ = false;   // read by power_on() from other threads
  bool restarting_ = false;  // a reset's restart_s: the device hears nothing until it has booted
  std::atomic<int> power_switch_ = -1;  // set_power(): 1 on, 0 off; -1 never switched
  boost::asio::steady_timer wake_writer_{io_, Clock::time_point::max()};
  boost::asio::steady_timer wake_source_{io_, Clock::time_point::max()};

  void open_pty();
  void hang_up();
  std::function<void(std::exception_ptr)> failure_reporter(const char* part);
  void enqueue(DeviceOutput output);
  void enqueue_send(std::vector<std::uint8_t> bytes);
  boost::asio::awaitable<void> wait(boost::asio::steady_timer& timer, Clock::duration d);
  boost::asio::awaitable<void> reader(std::uint64_t generation);
  boost::asio::awaitable<void> writer();
  // Puts bytes on the line: at time_scale 0 at once; else a scan when a line at the device's
  // rate would have carried its last byte, anything else at once and then holding the line for
  // its time.
  boost::asio::awaitable<void> send_on_line(const std::vector<std::uint8_t>& bytes, bool is_scan,
                                            boost::asio::steady_timer& pace);
  boost::asio::awaitable<void> restart();
  std::vector<std::uint8_t> draw_scan(std::vector<RangeReading>& readings, double& time_s);
};

}  // namespace tofcomp::sim::lms200
