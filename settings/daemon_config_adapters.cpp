// The configuration handed to the host driver and the emulator.
#include "settings/daemon_config_adapters.hpp"

#include "io/measured_data_csv.hpp"
#include "settings/daemon_config_error.hpp"
#include "sim/scenario_yaml.hpp"

namespace tofcomp::settings {

hal::lms2xx::DriverSettings driver_settings(const LinkConfig& link,
                                            const std::string& emulator_device) {
  hal::lms2xx::DriverSettings settings;
  settings.device = link.device.empty() ? emulator_device : link.device.string();
  settings.baud = link.baud;
  settings.variant = link.variant;
  settings.units = link.units;
  settings.measuring_mode = link.measuring_mode;
  settings.ack_timeout = link.ack_timeout;
  settings.reply_timeout = link.reply_timeout;
  settings.attempts = link.attempts;
  settings.scan_timeout = link.scan_timeout;
  settings.backoff_initial = link.backoff_initial;
  settings.backoff_max = link.backoff_max;
  return settings;
}

sim::lms200::EmulatorSettings emulator_settings(const DaemonConfig& config) {
  const EmulatorConfig& emulator = config.emulator;
  sim::lms200::EmulatorSettings settings;
  try {
    settings.scenario = sim::load_scenario_file(emulator.scenario.string());
  } catch (const core::Error& e) {
    throw DaemonConfigError(config.source + ": emulator.scenario (" + emulator.scenario.string() +
                            ") cannot be used: " + e.what());
  }
  if (!emulator.recording.empty()) {
    try {
      settings.recording = io::read_measured_data_file(emulator.recording.string());
      settings.recording_source = emulator.recording.string();
      // The daemon takes every recorded scan, and the recorded readings with it
      // (daemon/playback_feed.hpp): none is skipped while its driver brings the link up.
      settings.hold_recorded_scans = true;
    } catch (const core::Error& e) {
      throw DaemonConfigError(config.source + ": emulator.recording (" +
                              emulator.recording.string() + ") cannot be used: " + e.what());
    }
  }
  settings.identity.supports_500k = !emulator.rs232;
  settings.time_scale = emulator.time_scale;
  settings.faults = emulator.faults;
  settings.fault_seed = emulator.fault_seed;
  settings.link = emulator.link;
  return settings;
}

}  // namespace tofcomp::settings
