#include "daemon/private_directory.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include "core/error.hpp"

namespace tofcomp::daemon {

namespace {

constexpr mode_t kPrivateDirectoryMode = 0700;
constexpr mode_t kWritableByOthers = S_IWGRP | S_IWOTH;

std::string octal(mode_t mode) {
  char text[8] = {};
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

}  // namespace

void make_private_directory(const std::filesystem::path& directory) {
  const std::string name = directory.string();
  if (directory.has_parent_path()) {
    std::error_code ignored;  // a parent that cannot be made shows at the mkdir below, named
    std::filesystem::create_directories(directory.parent_path(), ignored);
  }
  if (::mkdir(directory.c_str(), kPrivateDirectoryMode) != 0 && errno != EEXIST) {
    throw core::Error("cannot make " + name + ": " + std::strerror(errno));
  }
  struct stat status {};
  if (::lstat(directory.c_str(), &status) != 0) {
    throw core::Error("cannot look at " + name + ": " + std::strerror(errno));
  }
  if (!S_ISDIR(status.st_mode)) {
    throw core::Error(name + " is not a directory (a symlink or a file is there): not publishing "
                      "in it; remove it or name another place (--socket PATH)");
  }
  if (status.st_uid != ::geteuid()) {
    throw core::Error(name + " belongs to uid " + std::to_string(status.st_uid) + ", not to uid " +
                      std::to_string(::geteuid()) +
                      ": not publishing in another user's folder; name another place (--socket "
                      "PATH) or set XDG_RUNTIME_DIR");
  }
  if ((status.st_mode & kWritableByOthers) != 0) {
    throw core::Error(name + " has mode " + octal(status.st_mode) +
                      ": others may write in it; not publishing there (chmod 700 " + name + ")");
  }
}

}  // namespace tofcomp::daemon
