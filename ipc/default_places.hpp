// Where tofcompd publishes and keeps its files when its configuration does not say, and where a
// client looks for it (docs/deployment.md, "Running as a normal user"). As root (the service),
// the system's places: the socket /run/tofcompd/tofcompd.sock, the ring /tofcompd and the state
// under /var/lib/tofcompd. As any other user, that user's own, as user services keep them: the
// socket under $XDG_RUNTIME_DIR/tofcompd, the ring /tofcompd.UID (the name a ring takes when
// another user holds /tofcompd, docs/shm-ring.md) and the state under $XDG_STATE_HOME/tofcompd
// ($HOME/.local/state/tofcompd). Without $XDG_RUNTIME_DIR, /tmp/tofcompd-UID stands in for it.
// A client run by a user reads that user's own daemon when its socket (ring) exists, and the
// system's otherwise.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>

namespace tofcomp::ipc {

// What the places depend on: who runs, and the environment's XDG variables (empty: unset).
struct UserEnvironment {
  uid_t uid = 0;
  std::string runtime_directory;  // $XDG_RUNTIME_DIR
  std::string state_home;         // $XDG_STATE_HOME
  std::string home;               // $HOME
};

// This process's: its effective uid and its environment.
UserEnvironment current_user_environment();

struct DaemonPlaces {
  std::filesystem::path socket;            // outputs.socket.path's default
  std::string ring;                        // outputs.shm.name's default
  std::filesystem::path state_directory;   // recordings go to its recordings/
  bool system = true;                      // the system's places (root), not a user's own
};

// The system's places, whoever runs.
DaemonPlaces system_places();

// The daemon's defaults for the user of `environment`: the system's for root, the user's own
// for anyone else. An XDG variable that is not an absolute path is ignored, as the XDG Base
// Directory specification asks.
DaemonPlaces daemon_places(const UserEnvironment& environment);

// The socket a client of that user connects to when none is named: the user's own daemon's when
// that socket exists, the system's otherwise.
std::filesystem::path socket_to_read(const UserEnvironment& environment);

// The ring a client of that user reads when none is named: the user's own daemon's when that
// shared-memory object exists (/dev/shm), the system's otherwise.
std::string ring_to_read(const UserEnvironment& environment);

}  // namespace tofcomp::ipc
