// The default configuration built into tofcompd: the text of config/tofcompd.yaml at build time
// (an emulated LMS 200 and its simulated case sensor, so that the daemon runs with no hardware).
#pragma once

#include <filesystem>
#include <string_view>

#include "settings/daemon_config.hpp"

namespace tofcomp::settings {

// config/tofcompd.yaml as it was when the library was built.
std::string_view embedded_default_config_text();

// Where the default's relative paths (its scenario, its calibration) point: the data directory
// beside the binary (io/data_directory.hpp), PREFIX/share/tofcomp once installed and
// build/share/tofcomp in the build tree, which hold copies of config/'s scenarios and
// calibration (config/CMakeLists.txt).
std::filesystem::path embedded_default_config_directory();

// The default, read like a file in `base_directory`. Throws DaemonConfigError.
DaemonConfig embedded_default_config(
    const std::filesystem::path& base_directory = embedded_default_config_directory());

}  // namespace tofcomp::settings
