// keys_needing_restart(): what a reload (SIGHUP) cannot change in the running daemon. The link,
// the emulator, the case sensor, the power lines, the outputs and the log target are set up once
// at start; calibration, compensation, recording, recalibration and the log level are applied
// live, so they are not compared here (docs/configuration.md, "Reloading").
#include <tuple>
#include <variant>

#include "settings/daemon_config.hpp"

namespace tofcomp::settings {

namespace {

class RestartKeys {
 public:
  RestartKeys(const DaemonConfig& old, const DaemonConfig& next) : old_(old), next_(next) {}

  // Lists `key` when `get` gives different values for the two configurations.
  template <class Get>
  void compare(const char* key, Get get) {
    if (!(get(old_) == get(next_))) keys_.emplace_back(key);
  }

  void link() {
    compare("link.device", [](const DaemonConfig& c) { return c.link.device; });
    compare("link.baud", [](const DaemonConfig& c) { return c.link.baud; });
    compare("link.variant", [](const DaemonConfig& c) { return c.link.variant; });
    compare("link.units", [](const DaemonConfig& c) { return c.link.units; });
    compare("link.measuring_mode", [](const DaemonConfig& c) { return c.link.measuring_mode; });
    compare("link.timeouts.ack_ms", [](const DaemonConfig& c) { return c.link.ack_timeout; });
    compare("link.timeouts.reply_ms", [](const DaemonConfig& c) { return c.link.reply_timeout; });
    compare("link.timeouts.scan_ms", [](const DaemonConfig& c) { return c.link.scan_timeout; });
    compare("link.attempts", [](const DaemonConfig& c) { return c.link.attempts; });
    compare("link.backoff.initial_ms",
            [](const DaemonConfig& c) { return c.link.backoff_initial; });
    compare("link.backoff.max_ms", [](const DaemonConfig& c) { return c.link.backoff_max; });
  }

  void emulator() {
    compare("emulator.enabled", [](const DaemonConfig& c) { return c.emulator.enabled; });
    compare("emulator.scenario", [](const DaemonConfig& c) { return c.emulator.scenario; });
    compare("emulator.recording", [](const DaemonConfig& c) { return c.emulator.recording; });
    compare("emulator.time_scale", [](const DaemonConfig& c) { return c.emulator.time_scale; });
    compare("emulator.faults.garbage",
            [](const DaemonConfig& c) { return c.emulator.faults.garbage; });
    compare("emulator.faults.dropped_byte",
            [](const DaemonConfig& c) { return c.emulator.faults.dropped_byte; });
    compare("emulator.faults.corrupted_crc",
            [](const DaemonConfig& c) { return c.emulator.faults.corrupted_crc; });
    compare("emulator.faults.stall", [](const DaemonConfig& c) { return c.emulator.faults.stall; });
    compare("emulator.faults.hang_up",
            [](const DaemonConfig& c) { return c.emulator.faults.hang_up; });
    compare("emulator.faults.reset", [](const DaemonConfig& c) { return c.emulator.faults.reset; });
    compare("emulator.faults.stall_s",
            [](const DaemonConfig& c) { return c.emulator.faults.stall_s; });
    compare("emulator.faults.max_garbage_bytes",
            [](const DaemonConfig& c) { return c.emulator.faults.max_garbage_bytes; });
    compare("emulator.fault_seed", [](const DaemonConfig& c) { return c.emulator.fault_seed; });
    compare("emulator.link", [](const DaemonConfig& c) { return c.emulator.link; });
    compare("emulator.rs232", [](const DaemonConfig& c) { return c.emulator.rs232; });
  }

  void case_sensor() {
    const auto& old_backend = old_.case_sensor.sensor.backend;
    const auto& next_backend = next_.case_sensor.sensor.backend;
    if (old_backend.index() != next_backend.index()) {
      keys_.emplace_back("case_sensor.backend");
    } else if (std::holds_alternative<hal::HwmonSensorConfig>(old_backend)) {
      const auto hwmon = [](const DaemonConfig& c) {
        return std::get<hal::HwmonSensorConfig>(c.case_sensor.sensor.backend);
      };
      compare("case_sensor.hwmon.directory",
              [&](const DaemonConfig& c) { return hwmon(c).directory; });
      compare("case_sensor.hwmon.name", [&](const DaemonConfig& c) { return hwmon(c).name; });
      compare("case_sensor.hwmon.channel", [&](const DaemonConfig& c) { return hwmon(c).channel; });
      compare("case_sensor.hwmon.root", [&](const DaemonConfig& c) { return hwmon(c).root; });
    } else if (std::holds_alternative<hal::I2cSensorConfig>(old_backend)) {
      const auto i2c = [](const DaemonConfig& c) {
        return std::get<hal::I2cSensorConfig>(c.case_sensor.sensor.backend);
      };
      compare("case_sensor.i2c.device", [&](const DaemonConfig& c) { return i2c(c).device; });
      compare("case_sensor.i2c.address", [&](const DaemonConfig& c) { return i2c(c).address; });
      compare("case_sensor.i2c.chip", [&](const DaemonConfig& c) { return i2c(c).chip; });
    } else if (std::holds_alternative<hal::W1SensorConfig>(old_backend)) {
      const auto w1 = [](const DaemonConfig& c) {
        return std::get<hal::W1SensorConfig>(c.case_sensor.sensor.backend);
      };
      compare("case_sensor.w1.device_id", [&](const DaemonConfig& c) { return w1(c).device_id; });
      compare("case_sensor.w1.root", [&](const DaemonConfig& c) { return w1(c).root; });
    } else {
      compare("case_sensor.simulated.description", [](const DaemonConfig& c) {
        return std::get<hal::SimulatedSensorConfig>(c.case_sensor.sensor.backend).description;
      });
    }
    compare("case_sensor.poll_interval_ms",
            [](const DaemonConfig& c) { return c.case_sensor.poll_interval; });
    compare("case_sensor.stale_after_s",
            [](const DaemonConfig& c) { return c.case_sensor.sensor.limits.max_age; });
    compare("case_sensor.limits.min_c",
            [](const DaemonConfig& c) { return c.case_sensor.sensor.limits.min_c; });
    compare("case_sensor.limits.max_c",
            [](const DaemonConfig& c) { return c.case_sensor.sensor.limits.max_c; });
    compare("case_sensor.limits.max_rate_c_per_s",
            [](const DaemonConfig& c) { return c.case_sensor.sensor.limits.max_rate_c_per_s; });
    compare("case_sensor.limits.jump_allowance_c",
            [](const DaemonConfig& c) { return c.case_sensor.sensor.limits.jump_allowance_c; });
  }

  void power() {
    const auto line = [](const std::optional<hal::GpioLineConfig>& l) {
      return l ? std::optional(std::tie(l->chip, l->line, l->active_low)) : std::nullopt;
    };
    compare("power.switch", [&](const DaemonConfig& c) { return line(c.power.power_switch); });
    compare("power.sense", [&](const DaemonConfig& c) { return line(c.power.sense); });
  }

  void outputs() {
    compare("outputs.socket.path", [](const DaemonConfig& c) { return c.outputs.socket.path; });
    compare("outputs.socket.mode", [](const DaemonConfig& c) { return c.outputs.socket.mode; });
    compare("outputs.socket.max_clients",
            [](const DaemonConfig& c) { return c.outputs.socket.max_clients; });
    compare("outputs.socket.max_request_bytes",
            [](const DaemonConfig& c) { return c.outputs.socket.max_request_bytes; });
    compare("outputs.socket.max_queued_bytes_per_client",
            [](const DaemonConfig& c) { return c.outputs.socket.max_queued_bytes_per_client; });
    compare("outputs.socket.idle_timeout_s",
            [](const DaemonConfig& c) { return c.outputs.socket.idle_timeout.count(); });
    compare("outputs.shm.name", [](const DaemonConfig& c) { return c.outputs.shm.name; });
    compare("outputs.shm.slots", [](const DaemonConfig& c) { return c.outputs.shm.slots; });
    compare("outputs.shm.mode", [](const DaemonConfig& c) { return c.outputs.shm.mode; });
  }

  void log() {
    compare("log.target", [](const DaemonConfig& c) { return c.log.target; });
  }

  std::vector<std::string> take() { return std::move(keys_); }

 private:
  const DaemonConfig& old_;
  const DaemonConfig& next_;
  std::vector<std::string> keys_;
};

}  // namespace

std::vector<std::string> keys_needing_restart(const DaemonConfig& old, const DaemonConfig& next) {
  RestartKeys keys(old, next);
  keys.link();
  keys.emulator();
  keys.case_sensor();
  keys.power();
  keys.outputs();
  keys.log();
  return keys.take();
}

}  // namespace tofcomp::settings
