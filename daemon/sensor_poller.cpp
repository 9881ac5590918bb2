#include "daemon/sensor_poller.hpp"

namespace tofcomp::daemon {

SensorPoller::SensorPoller(boost::asio::io_context& io,
                           std::unique_ptr<hal::TemperatureSensor> sensor,
                           std::chrono::milliseconds interval, Handler on_reading)
    : io_(io),
      sensor_(std::move(sensor)),
      description_(sensor_->describe()),
      interval_(interval),
      on_reading_(std::move(on_reading)) {}

SensorPoller::~SensorPoller() {
  stop();
}

void SensorPoller::start() {
  if (thread_.joinable()) return;
  stopping_ = false;
  thread_ = std::thread([this] { run(); });
}

void SensorPoller::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SensorPoller::run() {
  auto next = std::chrono::steady_clock::now();
  for (;;) {
    const hal::TemperatureReading reading = sensor_->read();
    const auto when = std::chrono::steady_clock::now();
    boost::asio::post(io_, [this, when, reading] { on_reading_(when, reading); });
    next += interval_;
    if (next < when) next = when;  // a read longer than the interval: no burst to catch up
    std::unique_lock lock(mutex_);
    if (wake_.wait_until(lock, next, [this] { return stopping_; })) return;
  }
}

}  // namespace tofcomp::daemon
