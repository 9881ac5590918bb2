// SO_PEERCRED and the control policy: see peer_credentials.hpp.
#include "daemon/socket/peer_credentials.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>

namespace tofcomp::daemon::socket {

namespace {
constexpr uid_t kRoot = 0;
}  // namespace

std::optional<PeerCredentials> peer_credentials(int fd) {
  ucred cred{};
  socklen_t length = sizeof cred;
  if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &length) != 0 || length != sizeof cred) {
    return std::nullopt;
  }
  return PeerCredentials{cred.pid, cred.uid, cred.gid};
}

ControlPolicy::ControlPolicy(std::vector<uid_t> control_uids) : uids_(std::move(control_uids)) {
  if (uids_.empty()) uids_ = {kRoot, ::geteuid()};
  std::sort(uids_.begin(), uids_.end());
  uids_.erase(std::unique(uids_.begin(), uids_.end()), uids_.end());
}

bool ControlPolicy::may_control(const std::optional<PeerCredentials>& peer) const {
  return peer && std::find(uids_.begin(), uids_.end(), peer->uid) != uids_.end();
}

std::string ControlPolicy::describe() const {
  std::string text;
  for (std::size_t i = 0; i < uids_.size(); ++i) {
    if (i > 0) text += i + 1 == uids_.size() ? " and " : ", ";
    text += describe_user(uids_[i]);
  }
  return text;
}

}  // namespace tofcomp::daemon::socket
