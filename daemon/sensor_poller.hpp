// Reads the case-temperature sensor on a thread of its own, every poll interval, and hands each
// reading to the event loop. A sensor read may block (a DS18B20 conversion takes up to 750 ms,
// an I2C bus may stall), so it never runs inside an Asio handler. Each reading is stamped on the
// daemon's monotonic clock when the read returns.
#pragma once

#include <boost/asio.hpp>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::daemon {

class SensorPoller {
 public:
  using Handler =
      std::function<void(std::chrono::steady_clock::time_point, const hal::TemperatureReading&)>;

  // on_reading runs on io's thread.
  SensorPoller(boost::asio::io_context& io, std::unique_ptr<hal::TemperatureSensor> sensor,
               std::chrono::milliseconds interval, Handler on_reading);
  ~SensorPoller();  // stop()
  SensorPoller(const SensorPoller&) = delete;
  SensorPoller& operator=(const SensorPoller&) = delete;

  void start();
  // Ends the thread (after a read in progress returns) and joins it.
  void stop();
  std::string describe() const { return description_; }

 private:
  void run();

  boost::asio::io_context& io_;
  std::unique_ptr<hal::TemperatureSensor> sensor_;
  std::string description_;
  std::chrono::milliseconds interval_;
  Handler on_reading_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace tofcomp::daemon
