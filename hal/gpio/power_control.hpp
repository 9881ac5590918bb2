// The scanner's power: a switch on a GPIO output and a sense line whose edges are delivered on
// a Boost.Asio io_context as they happen (the event descriptor is waited on, never polled).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <functional>
#include <memory>
#include <string>

#include "hal/gpio/gpio_line.hpp"

namespace tofcomp::hal {

// One GPIO line as the configuration names it.
struct GpioLineConfig {
  std::string chip;  // "gpiochip0", "0", "/dev/gpiochip0" or the chip's label
  std::string line;  // the line's offset ("17") or its name ("SCANNER_PWR")
  bool active_low = false;
};

// Throws core::InvalidInput naming `what` ("power switch") when chip or line is empty.
void check_gpio_line_config(const GpioLineConfig& config, const std::string& what);

class PowerSwitch {
 public:
  // Throws core::InvalidInput when `output` is null. The state starts as `initially_on`,
  // which must be what the output was requested with.
  explicit PowerSwitch(std::unique_ptr<GpioOutput> output, bool initially_on = false);

  // Drives the output; throws GpioError, leaving is_on() as it was, when that fails.
  void set(bool on);
  // The state last set successfully.
  bool is_on() const { return on_; }
  std::string describe() const { return output_->describe(); }

 private:
  std::unique_ptr<GpioOutput> output_;
  bool on_;
};

// Delivers each edge of a GpioEdgeSource to a handler on an io_context: the source's event
// descriptor is wrapped in a stream_descriptor and waited on with async_wait(wait_read); when it
// turns readable the pending edges are read and handed over in order, and the wait is renewed.
// The descriptor stays the source's: it is released, never closed, on destruction.
//
// Not thread-safe: construct, destroy and call it on the io_context's thread (or while the
// io_context is not running). Destruction cancels the wait; no handler runs afterwards, even
// one already queued.
class PowerSense {
 public:
  using EdgeHandler = std::function<void(const GpioEdge&)>;
  // Called once when reading the source fails; the sense then stops waiting.
  using ErrorHandler = std::function<void(const std::string&)>;

  // Starts waiting at once. Throws core::InvalidInput when `source` or `on_edge` is empty.
  PowerSense(boost::asio::io_context& io, std::unique_ptr<GpioEdgeSource> source,
             EdgeHandler on_edge, ErrorHandler on_error = {});
  ~PowerSense();
  PowerSense(const PowerSense&) = delete;
  PowerSense& operator=(const PowerSense&) = delete;

  // The line's present logical value (true: the scanner has power); throws GpioError.
  bool level() const { return source_->level(); }
  std::string describe() const { return source_->describe(); }

 private:
  void wait();

  std::unique_ptr<GpioEdgeSource> source_;
  EdgeHandler on_edge_;
  ErrorHandler on_error_;
  boost::asio::posix::stream_descriptor descriptor_;
  // Cleared by the destructor; every completion handler checks it before touching `this`.
  std::shared_ptr<bool> alive_;
};

// The libgpiod backends. Throw core::InvalidInput for an empty chip or line and GpioError
// naming chip, line and errno when the line cannot be requested.
PowerSwitch make_power_switch(const GpioLineConfig& config, bool initially_on = false);
std::unique_ptr<PowerSense> make_power_sense(boost::asio::io_context& io,
                                             const GpioLineConfig& config,
                                             PowerSense::EdgeHandler on_edge,
                                             PowerSense::ErrorHandler on_error = {});

}  // namespace tofcomp::hal
