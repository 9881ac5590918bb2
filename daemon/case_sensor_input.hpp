// The case temperature as the pipeline gets it: the configured sensor, polled on a thread of its
// own (daemon/sensor_poller.hpp) and stamped on the daemon's clock; or, while the link plays a
// recording, the recorded readings its playback hands over. Owns the poller, the sensor's state
// and the counts of valid and invalid readings.
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "daemon/event_clock.hpp"
#include "daemon/sensor_poller.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

struct SensorCounters {
  std::uint64_t readings_valid = 0;
  std::uint64_t readings_invalid = 0;  // implausible, stale, missing: logged, not used
};

class CaseSensorInput {
 public:
  // A valid reading, on the loop, on the daemon's clock.
  using Reading = std::function<void(double time_s, double case_c)>;

  // played_recording: the recording the link plays, whose readings come through recorded();
  // nullopt: the configured sensor is polled, the simulated one reading `simulated_source`.
  // Throws core::InvalidInput for a sensor configuration that cannot work.
  CaseSensorInput(boost::asio::io_context& io, const settings::CaseSensorConfig& config,
                  std::optional<std::filesystem::path> played_recording,
                  std::function<double()> simulated_source, const EventClock& clock,
                  Reading on_reading);

  void start();
  void stop();
  // Playing a recording: a recorded reading, at its recorded time.
  void recorded(double time_s, double case_c);

  // The backend, for the status.
  std::string describe() const;
  const std::string& state() const { return state_; }
  const SensorCounters& counters() const { return counters_; }

 private:
  void on_poll(std::chrono::steady_clock::time_point when, const hal::TemperatureReading& r);
  void take(double time_s, double case_c);  // a valid reading

  std::optional<std::filesystem::path> played_recording_;
  const EventClock& clock_;
  Reading on_reading_;
  std::unique_ptr<SensorPoller> poller_;  // null while playing a recording
  std::string state_ = "no reading yet";
  SensorCounters counters_;
};

}  // namespace tofcomp::daemon
