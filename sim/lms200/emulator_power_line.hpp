// The emulated LMS 200's supply as a GPIO output, so that a hal::PowerSwitch switches the
// in-process emulated scanner (emulator.hpp) as it would a real one's supply: the daemon's power
// switch when the embedded default runs without hardware (emulated_scanner_device.hpp).
#pragma once

#include <string>

#include "hal/gpio/gpio_line.hpp"
#include "sim/lms200/emulator.hpp"

namespace tofcomp::sim::lms200 {

class EmulatorPowerLine : public hal::GpioOutput {
 public:
  // `emulator` must outlive the line.
  explicit EmulatorPowerLine(Emulator& emulator) : emulator_(emulator) {}

  // Active: the scanner is powered (Emulator::set_power).
  void set(bool active) override { emulator_.set_power(active); }
  bool get() const override { return emulator_.power_on(); }
  std::string describe() const override { return "the emulated LMS 200's supply"; }

 private:
  Emulator& emulator_;
};

}  // namespace tofcomp::sim::lms200
