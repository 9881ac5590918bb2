// The rules of the two names a daemon publishes under, shared by the configuration's keys
// (outputs.socket.path, outputs.shm.name) and the command line's overrides (--socket, --shm).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace tofcomp::settings {

// sockaddr_un::sun_path holds 108 bytes on Linux, the terminating NUL included.
inline constexpr std::size_t kMaxSocketPathBytes = 107;
// NAME_MAX for the name of a POSIX shared-memory object under /dev/shm.
inline constexpr std::size_t kMaxShmNameBytes = 255;

// What is wrong with a resolved socket path ("is N bytes long once resolved; ..."), or "" when
// nothing is.
std::string socket_path_problem(const std::filesystem::path& path);

// What is wrong with a shared-memory name ("must be a shared-memory name like ..."), or "".
std::string shm_name_problem(const std::string& name);

}  // namespace tofcomp::settings
