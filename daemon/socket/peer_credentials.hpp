// Who is on the other end of a Unix-socket connection, as the kernel recorded it when the peer
// connected (SO_PEERCRED), and the server's rule for who may control the daemon
// (docs/protocol.md, "Who may do what").
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "ipc/user_name.hpp"

namespace tofcomp::daemon::socket {

struct PeerCredentials {
  pid_t pid = 0;
  uid_t uid = 0;
  gid_t gid = 0;
};

// The credentials of the peer of connected socket fd; nullopt when the kernel gives none.
std::optional<PeerCredentials> peer_credentials(int fd);

// Control requests (reload, recalibrate) are for these users; reading requests for anyone who
// can connect. Built from the server's setting: its listed users, or when it lists none, the
// server's own effective user and root.
class ControlPolicy {
 public:
  explicit ControlPolicy(std::vector<uid_t> control_uids);

  bool may_control(const std::optional<PeerCredentials>& peer) const;
  // "uid 0 (root) and uid 999 (tofcompd)": the users named in refusals.
  std::string describe() const;

 private:
  std::vector<uid_t> uids_;
};

using ipc::describe_user;

}  // namespace tofcomp::daemon::socket
