// A folder only its user may write: where a normal user's tofcompd keeps its socket and lock by
// default (ipc/default_places.hpp). Under /tmp (no $XDG_RUNTIME_DIR) anyone could have made the
// folder first, or a symlink in its place, to catch the socket; so the folder is used only when
// it is a real directory of this user that no one else may write.
#pragma once

#include <filesystem>

namespace tofcomp::daemon {

// Makes `directory` (mode 0700; its parents as the umask allows) when it is missing, then checks
// it. Throws core::Error naming it and what is wrong: not a directory (a symlink counts as not),
// another user's, or writable by its group or others.
void make_private_directory(const std::filesystem::path& directory);

}  // namespace tofcomp::daemon
