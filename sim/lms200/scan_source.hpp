// Where the emulated LMS 200's scans come from: the digital twin (twin_scan_source.hpp) or a
// tofcompd recording played back (recording_scan_source.hpp). The link on the pty
// (pty_link.hpp) sends what a source draws; the source paces the scans onto the link and tells
// the link when the scanner's power changes. Used inside sim/ only (it needs Boost.Asio).
#pragma once

#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <vector>

#include "sim/lms200/device.hpp"

namespace tofcomp::sim::lms200 {

class PtyLink;

// A duration on the wall clock, in the steady clock's resolution.
inline std::chrono::nanoseconds wall_duration(double seconds) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::duration<double>(seconds));
}

// A scan as the source drew it, before the device encodes it.
struct DrawnScan {
  std::vector<RangeReading> readings;
  double time_s = 0.0;  // the source's time of the scan
};

class ScanSource {
 public:
  virtual ~ScanSource() = default;

  // These run with the link's state mutex held (PtyLink::state_mutex()).
  // Whether the scanner is powered by the source's own account (schedule or recording).
  virtual bool power_on() const = 0;
  // The case sensor on the scanner now.
  virtual double read_case_sensor() = 0;
  // The source's clock, seconds since it began.
  virtual double time_s() const = 0;
  // The scanner's supply switched from outside (Emulator::set_power).
  virtual void override_power(bool on) = 0;
  // The scan the link is about to send, as the device is configured.
  virtual DrawnScan draw_scan(const Lms200Device& device) = 0;

  // Paces the scans onto the link, on the link's thread, until the link stops; ends with an
  // exception only on a failure.
  virtual boost::asio::awaitable<void> stream(PtyLink& link) = 0;
};

}  // namespace tofcomp::sim::lms200
