#include "ipc/default_places.hpp"

#include <unistd.h>

#include <cstdlib>

#include "ipc/ring/ring_layout.hpp"
#include "ipc/ring/shm_object.hpp"
#include "ipc/socket/protocol_constants.hpp"

namespace tofcomp::ipc {

namespace {

constexpr uid_t kRootUid = 0;
constexpr const char* kSystemStateDirectory = "/var/lib/tofcompd";
constexpr const char* kPlaceName = "tofcompd";  // the folder under each base directory
constexpr const char* kSocketFileName = "tofcompd.sock";
// Stands in for $XDG_RUNTIME_DIR when it is not set (a shell without a login session): a
// folder of the user's under the temporary directory.
constexpr const char* kRuntimeFallbackPrefix = "/tmp/tofcompd-";
constexpr const char* kStateUnderHome = ".local/state";

std::string variable(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr ? std::string(value) : std::string();
}

// The XDG Base Directory rule: a relative path in the variable is invalid and ignored.
bool usable(const std::string& directory) {
  return !directory.empty() && std::filesystem::path(directory).is_absolute();
}

std::filesystem::path runtime_base(const UserEnvironment& environment) {
  if (usable(environment.runtime_directory)) {
    return std::filesystem::path(environment.runtime_directory) / kPlaceName;
  }
  return kRuntimeFallbackPrefix + std::to_string(environment.uid);
}

std::filesystem::path state_base(const UserEnvironment& environment) {
  if (usable(environment.state_home)) return std::filesystem::path(environment.state_home) / kPlaceName;
  if (usable(environment.home)) {
    return std::filesystem::path(environment.home) / kStateUnderHome / kPlaceName;
  }
  return runtime_base(environment) / "state";
}

DaemonPlaces own_places(const UserEnvironment& environment) {
  return {runtime_base(environment) / kSocketFileName,
          ring::alternative_ring_name(ring::kDefaultRingName, environment.uid),
          state_base(environment), false};
}

}  // namespace

UserEnvironment current_user_environment() {
  return {::geteuid(), variable("XDG_RUNTIME_DIR"), variable("XDG_STATE_HOME"), variable("HOME")};
}

DaemonPlaces system_places() {
  return {socket::kDefaultSocketPath, ring::kDefaultRingName, kSystemStateDirectory, true};
}

DaemonPlaces daemon_places(const UserEnvironment& environment) {
  return environment.uid == kRootUid ? system_places() : own_places(environment);
}

std::filesystem::path socket_to_read(const UserEnvironment& environment) {
  if (environment.uid != kRootUid) {
    const std::filesystem::path own = own_places(environment).socket;
    std::error_code ignored;
    if (std::filesystem::exists(own, ignored)) return own;
  }
  return system_places().socket;
}

std::string ring_to_read(const UserEnvironment& environment) {
  if (environment.uid != kRootUid) {
    std::string own = own_places(environment).ring;
    if (ring::object_owner(own)) return own;
  }
  return system_places().ring;
}

}  // namespace tofcomp::ipc
