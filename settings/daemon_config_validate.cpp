// validate(): the rules of tofcompd.yaml that join two or more keys, each failure naming every
// key involved. A key's own type and range are the section readers' to check.
#include <string>
#include <utility>

#include "io/yaml_typed_fields.hpp"
#include "settings/daemon_config.hpp"
#include "settings/daemon_config_error.hpp"

namespace tofcomp::settings {

namespace {

using io::fields::format_number;

class Rules {
 public:
  explicit Rules(const DaemonConfig& config)
      : config_(config), source_(config.source.empty() ? "configuration" : config.source) {}

  void require(bool holds, const std::string& why) const {
    if (!holds) throw DaemonConfigError(source_ + ": " + why);
  }

  void link() const {
    const LinkConfig& link = config_.link;
    require(link.variant.is_valid(), "link.variant.resolution_deg " +
                                         format_number(link.variant.resolution_centideg / 100.0) +
                                         " does not exist with link.variant.field_deg " +
                                         std::to_string(link.variant.angle_deg) +
                                         " (0.25 needs field_deg 100)");
    require(link.backoff_max >= link.backoff_initial,
            "link.backoff.max_ms (" + std::to_string(link.backoff_max.count()) +
                ") must be at least link.backoff.initial_ms (" +
                std::to_string(link.backoff_initial.count()) + ")");
  }

  void emulator() const {
    const EmulatorConfig& emulator = config_.emulator;
    require(emulator.faults.total() <= 1.0, "emulator.faults: the rates add up to " +
                                                format_number(emulator.faults.total()) +
                                                " per telegram; they must add up to at most 1");
    if (emulator.enabled) {
      require(!emulator.scenario.empty(),
              "emulator.scenario is missing (emulator.enabled is true)");
      require(config_.link.device == emulator.link,
              "link.device (" + config_.link.device.string() +
                  ") must be left out while emulator.enabled is true: the driver opens the "
                  "emulated device (emulator.link" +
                  (emulator.link.empty() ? std::string(", or its pty")
                                         : ", " + emulator.link.string()) +
                  ")");
      require(!(emulator.rs232 && config_.link.baud == 500000),
              "link.baud 500000 is refused by an RS-232 unit (emulator.rs232 is true); use "
              "38400 or less");
    } else {
      require(!config_.link.device.empty(),
              "link.device is missing: give the serial port, or set emulator.enabled: true");
    }
  }

  void case_sensor() const {
    const CaseSensorConfig& sensor = config_.case_sensor;
    require(!std::holds_alternative<hal::SimulatedSensorConfig>(sensor.sensor.backend) ||
                config_.emulator.enabled,
            "case_sensor.backend simulated reads the emulator's twin: it needs "
            "emulator.enabled: true");
    require(config_.emulator.recording.empty() ||
                std::holds_alternative<hal::SimulatedSensorConfig>(sensor.sensor.backend),
            "emulator.recording plays the recorded case readings to the daemon: "
            "case_sensor.backend must be simulated");
    const auto& limits = sensor.sensor.limits;
    require(limits.min_c < limits.max_c,
            "case_sensor.limits.min_c (" + format_number(limits.min_c) +
                ") must be below case_sensor.limits.max_c (" + format_number(limits.max_c) + ")");
    require(limits.max_age.count() * 1000.0 > static_cast<double>(sensor.poll_interval.count()),
            "case_sensor.stale_after_s (" + format_number(limits.max_age.count()) +
                " s) must be longer than case_sensor.poll_interval_ms (" +
                std::to_string(sensor.poll_interval.count()) + " ms)");
  }

  void compensation() const {
    const CompensationConfig& compensation = config_.compensation;
    require(compensation.window.min_samples <= compensation.window.window,
            "compensation.min_samples (" + std::to_string(compensation.window.min_samples) +
                ") must be at most compensation.window (" +
                std::to_string(compensation.window.window) + ")");
  }

  void recalibration() const {
    const RecalibrationConfig& recal = config_.recalibration;
    if (recal.source == RecalibrationSource::None) {
      require(recal.trigger == RecalibrationTrigger::OnRequest,
              "recalibration.trigger at_start_if_missing needs a recalibration.source other than "
              "none");
      return;
    }
    require(!recal.output.empty(),
            "recalibration.output is missing: give it, or calibration.file for it to default to");
    require(recal.datasheet.empty() || recal.output != recal.datasheet,
            "recalibration.output must not be recalibration.datasheet (" +
                recal.datasheet.string() + ")");
    if (recal.source == RecalibrationSource::Recording) {
      require(!recal.data.empty(), "recalibration.recording.data is missing");
      require(recal.output != recal.data,
              "recalibration.output must not be recalibration.recording.data (" +
                  recal.data.string() + ")");
    } else {
      power_cycle_run();
    }
    if (recal.trigger == RecalibrationTrigger::AtStartIfMissing) {
      require(!config_.calibration.file.empty() && recal.output == config_.calibration.file,
              "recalibration.trigger at_start_if_missing makes calibration.file when it is "
              "missing: calibration.file must be given and recalibration.output (" +
                  recal.output.string() + ") must be it");
    }
  }

 private:
  void power_cycle_run() const {
    const RecalibrationConfig& recal = config_.recalibration;
    const PowerCycleRunConfig& run = recal.power_cycle_run;
    require(config_.power.power_switch.has_value() || config_.emulator.enabled,
            "recalibration.source power_cycle_run switches the scanner's power: it needs "
            "power.switch (or emulator.enabled: true, whose scanner it switches)");
    const int beams = config_.link.variant.values_per_scan();
    require(run.beams.last < beams,
            "recalibration.power_cycle_run.beams.last " + std::to_string(run.beams.last) +
                " is beyond the scan of link.variant (" +
                std::to_string(config_.link.variant.angle_deg) + "° at " +
                format_number(config_.link.variant.resolution_centideg / 100.0) +
                "°), whose beams are 0 to " + std::to_string(beams - 1));
    require(!run.recording.empty(), "recalibration.power_cycle_run.recording is missing");
    for (const auto& [other, key] : {std::pair{recal.output, "recalibration.output"},
                                     std::pair{recal.datasheet, "recalibration.datasheet"}}) {
      require(other.empty() || run.recording != other, "recalibration.power_cycle_run.recording must not be " +
                                          std::string(key) + " (" + other.string() + ")");
    }
  }

  const DaemonConfig& config_;
  std::string source_;
};

}  // namespace

void validate(const DaemonConfig& config) {
  const Rules rules(config);
  rules.link();
  rules.emulator();
  rules.case_sensor();
  rules.compensation();
  rules.recalibration();
}

}  // namespace tofcomp::settings
