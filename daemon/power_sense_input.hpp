// The scanner's power as the configured power-sense line (`power.sense`) reports it: its level
// at start, then each edge, on the daemon's clock. Owns the sense line; without one, nothing.
#pragma once

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <optional>

#include "daemon/event_clock.hpp"
#include "hal/gpio/power_control.hpp"

namespace tofcomp::daemon {

class PowerSenseInput {
 public:
  // On the loop: the power's state.
  using Power = std::function<void(double time_s, bool on)>;

  // Reports the line's level at once. Throws core::Error naming the line when it cannot open.
  PowerSenseInput(boost::asio::io_context& io, const std::optional<hal::GpioLineConfig>& sense,
                  const EventClock& clock, Power on_power);

 private:
  const EventClock& clock_;
  Power on_power_;
  std::unique_ptr<hal::PowerSense> sense_;
};

}  // namespace tofcomp::daemon
