// The GPIO seam: an output line (the scanner's power switch) and a source of edges on an input
// line (its power-good sense), narrow enough for fakes in tests. gpiod_lines.hpp is the real
// backend on libgpiod.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tofcomp::hal {

// A GPIO operation failed; the message names the chip, the line and the system error.
class GpioError : public core::Error {
 public:
  GpioError(const std::string& what, int error_number)
      : core::Error(what), error_number_(error_number) {}
  int error_number() const { return error_number_; }

 private:
  int error_number_;
};

// One edge of an input line. `rising` means the line became active (its logical value went to
// 1: with active-low lines, the physical level fell). `timestamp` is the source's clock (the
// kernel's event time stamp for libgpiod).
struct GpioEdge {
  bool rising;
  std::chrono::nanoseconds timestamp;
};

class GpioOutput {
 public:
  virtual ~GpioOutput() = default;
  // Drives the line active (true) or inactive; throws GpioError on failure.
  virtual void set(bool active) = 0;
  // The logical value of the line; throws GpioError on failure.
  virtual bool get() const = 0;
  virtual std::string describe() const = 0;
};

class GpioEdgeSource {
 public:
  virtual ~GpioEdgeSource() = default;
  // A descriptor that polls readable while an edge is pending. Owned by the source: it stays
  // open as long as the source lives, and no one else closes it.
  virtual int event_fd() const = 0;
  // The pending edges, oldest first; empty when none is pending (never blocks). Throws
  // GpioError on failure.
  virtual std::vector<GpioEdge> read_edges() = 0;
  // The present logical value of the line; throws GpioError on failure.
  virtual bool level() const = 0;
  virtual std::string describe() const = 0;
};

}  // namespace tofcomp::hal
