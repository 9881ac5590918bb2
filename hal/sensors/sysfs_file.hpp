// Reading the small text files of sysfs (hwmon, w1) with the errno of a failure kept, so that a
// backend can tell a missing device (ENOENT) from a failing one (EIO, ENODATA).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "hal/sensors/temperature_sensor.hpp"

namespace tofcomp::hal {

struct SysfsRead {
  int error = 0;        // errno of the failed open or read; 0 on success
  std::string content;  // the file's whole text (sysfs attributes are at most a page)
};

SysfsRead read_sysfs_file(const std::filesystem::path& file);

// The validity a failed open or read means: Missing when the file or device is not there
// (ENOENT, ENODEV, ENXIO), ReadError otherwise.
ReadingValidity validity_of_errno(int error);

// The system's text for an errno value ("No such file or directory").
std::string errno_text(int error);

// `text` without leading and trailing blanks and line ends.
std::string_view trim(std::string_view text);

}  // namespace tofcomp::hal
