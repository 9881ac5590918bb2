// The listening socket a service manager passes to tofcompd (socket activation, sd_listen_fds(3)):
// systemd's tofcompd.socket, or `systemd-socket-activate -l PATH tofcompd` by hand. The manager
// binds the socket before the daemon starts, so clients may connect at once and wait in its
// queue; the daemon serves on it instead of binding its own.
#pragma once

#include <optional>
#include <string>

namespace tofcomp::daemon::service {

struct ActivatedSocket {
  int fd = -1;       // open for the whole process; the server serves on a duplicate of it
  std::string path;  // the file system path it is bound to
};

// The socket passed to this process, taken once: the LISTEN_* variables are unset so that no
// child (the training worker) takes it too. std::nullopt when none was passed (LISTEN_PID not
// this process, or LISTEN_FDS unset). Throws core::Error naming what was passed when it is not
// one listening Unix stream socket bound to a path: several sockets, a datagram socket, a TCP
// socket, one not listening.
std::optional<ActivatedSocket> take_activated_socket();

}  // namespace tofcomp::daemon::service
