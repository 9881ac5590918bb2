// Helpers for the configuration tests: parse a text, or take the message of the error it must
// raise (any other exception, or none, fails the test).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "settings/daemon_config_yaml.hpp"

namespace tofcomp::settings::testing {

inline const std::filesystem::path kSourceRoot = TOFCOMP_SOURCE_ROOT;
inline const std::filesystem::path kConfigDir = kSourceRoot / "config";

// The smallest valid configuration for a real host: a serial port and a case sensor.
inline const std::string kMinimal =
    "link: {device: /dev/ttyS0}\n"
    "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n";

inline DaemonConfig parse(const std::string& text) {
  return parse_daemon_config(text, "test.yaml", "/etc/tofcompd");
}

// The message of the DaemonConfigError that parsing `text` raises; "" (and a test failure)
// when it parses or raises anything else.
inline std::string error_of(const std::string& text) {
  try {
    parse(text);
    ADD_FAILURE() << "parsed without error:\n" << text;
  } catch (const DaemonConfigError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "raised another type of error: " << e.what();
  }
  return "";
}

}  // namespace tofcomp::settings::testing
