// Reads tofcompd.yaml (docs/configuration.md) strictly: an unknown key anywhere, a value of the
// wrong type, out of its range or not one of its choices, a missing required key, and keys that
// contradict one another (validate()) are errors naming the source and the key path; a syntax
// error names the line and column. Relative paths are resolved against the directory of the
// file, so a configuration can sit beside its scenario and calibration files.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "ipc/default_places.hpp"
#include "settings/daemon_config.hpp"
#include "settings/daemon_config_error.hpp"

namespace tofcomp::settings {

// The defaults of outputs.socket.path, outputs.shm.name and recording.directory for who runs
// (ipc/default_places.hpp: the system's as root, the user's own otherwise).
ipc::DaemonPlaces default_places_for_this_user();

// Reads and checks `file`; relative paths in it are resolved against its directory; the places
// it does not name are `places`. Throws DaemonConfigError, and nothing else, for a file that
// cannot be read or is not a valid configuration.
DaemonConfig load_daemon_config(const std::filesystem::path& file,
                                const ipc::DaemonPlaces& places = default_places_for_this_user());

// The same on text already read: `source_name` starts every message and becomes
// DaemonConfig::source; relative paths are resolved against `base_directory` (the current
// directory when empty). Reads no file. Throws DaemonConfigError, and nothing else.
DaemonConfig parse_daemon_config(std::string_view text, const std::string& source_name,
                                 const std::filesystem::path& base_directory = {},
                                 const ipc::DaemonPlaces& places = default_places_for_this_user());

}  // namespace tofcomp::settings
