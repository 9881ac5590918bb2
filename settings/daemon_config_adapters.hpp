// The configuration handed to the modules it configures: the host driver's settings from
// `link`, the emulator's settings (its scenario loaded) from `emulator`. The sensor, GPIO and
// window settings are the modules' own structs already (hal::SensorConfig, hal::GpioLineConfig,
// core::SlidingWindowOptions).
#pragma once

#include <string>

#include "hal/lms2xx/host_driver.hpp"
#include "settings/daemon_config.hpp"
#include "sim/lms200/emulator.hpp"

namespace tofcomp::settings {

// The driver's settings; the port is link.device, or `emulator_device` when that is empty (the
// emulator runs without a link path: pass Emulator::device_path()).
hal::lms2xx::DriverSettings driver_settings(const LinkConfig& link,
                                            const std::string& emulator_device = {});

// Loads emulator.scenario and builds the emulator's settings. Throws DaemonConfigError naming
// config.source and emulator.scenario when the scenario cannot be read or is not valid.
sim::lms200::EmulatorSettings emulator_settings(const DaemonConfig& config);

}  // namespace tofcomp::settings
