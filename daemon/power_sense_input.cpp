#include "daemon/power_sense_input.hpp"

#include <spdlog/spdlog.h>

#include <string>
#include <utility>

namespace tofcomp::daemon {

PowerSenseInput::PowerSenseInput(boost::asio::io_context& io,
                                 const std::optional<hal::GpioLineConfig>& sense,
                                 const EventClock& clock, Power on_power)
    : clock_(clock), on_power_(std::move(on_power)) {
  if (!sense) return;
  sense_ = hal::make_power_sense(
      io, *sense, [this](const hal::GpioEdge& edge) { on_power_(clock_.now_s(), edge.rising); },
      [](const std::string& why) { spdlog::error("power sense: {}", why); });
  on_power_(clock_.now_s(), sense_->level());
}

}  // namespace tofcomp::daemon
