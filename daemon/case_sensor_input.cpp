#include "daemon/case_sensor_input.hpp"

#include <spdlog/spdlog.h>

#include <utility>

#include "hal/sensors/sensor_config.hpp"

namespace tofcomp::daemon {

CaseSensorInput::CaseSensorInput(boost::asio::io_context& io,
                                 const settings::CaseSensorConfig& config,
                                 std::optional<std::filesystem::path> played_recording,
                                 std::function<double()> simulated_source, const EventClock& clock,
                                 Reading on_reading)
    : played_recording_(std::move(played_recording)),
      clock_(clock),
      on_reading_(std::move(on_reading)) {
  if (played_recording_) return;
  poller_ = std::make_unique<SensorPoller>(
      io, hal::make_temperature_sensor(config.sensor, std::move(simulated_source)),
      config.poll_interval,
      [this](std::chrono::steady_clock::time_point when, const hal::TemperatureReading& r) {
        on_poll(when, r);
      });
}

void CaseSensorInput::start() {
  if (poller_) poller_->start();
}

void CaseSensorInput::stop() {
  if (poller_) poller_->stop();
}

void CaseSensorInput::recorded(double time_s, double case_c) {
  take(time_s, case_c);
}

void CaseSensorInput::take(double time_s, double case_c) {
  ++counters_.readings_valid;
  state_ = "valid";
  on_reading_(time_s, case_c);
}

std::string CaseSensorInput::describe() const {
  return poller_ ? poller_->describe()
                 : "recorded case readings (" + played_recording_->string() + ")";
}

void CaseSensorInput::on_poll(std::chrono::steady_clock::time_point when,
                              const hal::TemperatureReading& r) {
  if (!r.valid()) {
    ++counters_.readings_invalid;
    state_ = std::string(hal::to_string(r.validity)) + ": " + r.detail;
    spdlog::warn("case sensor: {}", state_);
    return;
  }
  take(clock_.seconds(when), r.celsius);
}

}  // namespace tofcomp::daemon
