#include "hal/gpio/power_control.hpp"

#include <exception>
#include <utility>

#include "core/error.hpp"
#include "hal/gpio/gpiod_lines.hpp"

namespace tofcomp::hal {

void check_gpio_line_config(const GpioLineConfig& config, const std::string& what) {
  if (config.chip.empty())
    throw core::InvalidInput(what + ": gpio chip is empty (line '" + config.line + "')");
  if (config.line.empty())
    throw core::InvalidInput(what + ": gpio line is empty (chip '" + config.chip + "')");
}

PowerSwitch::PowerSwitch(std::unique_ptr<GpioOutput> output, bool initially_on)
    : output_(std::move(output)), on_(initially_on) {
  if (!output_) throw core::InvalidInput("power switch: no gpio output given");
}

void PowerSwitch::set(bool on) {
  output_->set(on);
  on_ = on;
}

PowerSense::PowerSense(boost::asio::io_context& io, std::unique_ptr<GpioEdgeSource> source,
                       EdgeHandler on_edge, ErrorHandler on_error)
    : source_(std::move(source)),
      on_edge_(std::move(on_edge)),
      on_error_(std::move(on_error)),
      descriptor_(io),
      alive_(std::make_shared<bool>(true)) {
  if (!source_) throw core::InvalidInput("power sense: no gpio edge source given");
  if (!on_edge_) throw core::InvalidInput("power sense " + source_->describe() + ": no handler");
  descriptor_.assign(source_->event_fd());
  wait();
}

PowerSense::~PowerSense() {
  *alive_ = false;
  boost::system::error_code ignored;
  descriptor_.cancel(ignored);
  // Hands the descriptor back without closing it: it belongs to the source.
  descriptor_.release();
}

void PowerSense::wait() {
  descriptor_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                         [this, alive = alive_](const boost::system::error_code& error) {
                           if (!*alive || error == boost::asio::error::operation_aborted) return;
                           std::string failure;
                           if (error) {
                             failure = "waiting for edges failed: " + error.message();
                           } else {
                             try {
                               for (const GpioEdge& edge : source_->read_edges()) {
                                 on_edge_(edge);
                                 // The handler may have destroyed this sense.
                                 if (!*alive) return;
                               }
                             } catch (const GpioError& e) {
                               failure = e.what();
                             }
                           }
                           if (failure.empty()) {
                             wait();
                           } else if (on_error_) {
                             on_error_(source_->describe() + ": " + failure);
                           }
                         });
}

PowerSwitch make_power_switch(const GpioLineConfig& config, bool initially_on) {
  check_gpio_line_config(config, "power switch");
  return PowerSwitch(
      std::make_unique<GpiodOutput>(config.chip, config.line, config.active_low, initially_on),
      initially_on);
}

std::unique_ptr<PowerSense> make_power_sense(boost::asio::io_context& io,
                                             const GpioLineConfig& config,
                                             PowerSense::EdgeHandler on_edge,
                                             PowerSense::ErrorHandler on_error) {
  check_gpio_line_config(config, "power sense");
  return std::make_unique<PowerSense>(
      io, std::make_unique<GpiodEdgeSource>(config.chip, config.line, config.active_low),
      std::move(on_edge), std::move(on_error));
}

}  // namespace tofcomp::hal
