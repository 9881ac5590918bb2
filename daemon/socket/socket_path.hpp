// The file system side of the server's socket: a stale socket file (left by a daemon that died)
// is removed only when nothing listens on it; a live one, or a file that is not a socket, makes
// start-up fail. At stop the server removes the socket file only if it is still the one it made.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace tofcomp::daemon::socket {

// True when a process accepts connections on the Unix socket at path (a connection attempt
// succeeds or finds its queue full); false when the connection is refused or the path is gone.
// Throws core::Error when it cannot tell (e.g. permission denied).
bool someone_listens(const std::string& path);

// Makes path free for a new listener. Returns true when it removed a stale socket file.
// Throws core::Error when another process listens there ("another tofcompd ..."), when the
// path holds something that is not a socket, or when removing fails.
bool clear_stale_socket(const std::string& path);

// Which file a path names, to recognise the socket file this server made.
struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator==(const FileIdentity&) const = default;
};
std::optional<FileIdentity> identity_of(const std::string& path);

// Removes path if it is still the file made (identity); leaves another daemon's socket alone.
void remove_if_same(const std::string& path, const FileIdentity& made);

}  // namespace tofcomp::daemon::socket
