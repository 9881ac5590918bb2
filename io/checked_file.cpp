// Checked opening of named files: see checked_file.hpp.
#include "io/checked_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.hpp"
#include "core/printable_text.hpp"

namespace tofcomp::io {

namespace {

constexpr std::size_t kReadChunk = 1 << 16;

std::string kind_of(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

[[noreturn]] void refuse(const std::string& what, const std::filesystem::path& path,
                         const std::string& why) {
  // The path may be a client's (a recording it named): escaped, so that it cannot cut or split
  // the message and the log line that carry it.
  throw core::InvalidInput(what + " " + core::printable(path.string()) + ": " + why);
}

// Opens name relative to dirfd (AT_FDCWD: the working directory) without blocking and, unless
// follow_links, without following a link at its last component; then checks what the
// descriptor is.
CheckedFile open_at(int dirfd, const std::string& name, const std::filesystem::path& shown,
                    std::uint64_t max_bytes, const std::string& what, const std::string& cap_name,
                    bool follow_links) {
  const int fd =
      ::openat(dirfd, name.c_str(),
               O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC | (follow_links ? 0 : O_NOFOLLOW));
  if (fd < 0) {
    const int error = errno;
    if (error == ELOOP) {
      refuse(what, shown,
             "a symbolic link; it must be the file itself (links are not followed, so that none "
             "leads elsewhere)");
    }
    if (error == ENOENT) refuse(what, shown, "does not exist");
    refuse(what, shown, std::string("cannot be opened: ") + std::strerror(error));
  }
  CheckedFile guard(fd, 0, shown);  // closes the descriptor if the file is refused
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    refuse(what, shown, std::string("fstat failed: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) {
    refuse(what, shown, kind_of(st.st_mode) + ", not a regular file; it is not read");
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes) {
    refuse(what, shown,
           std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) + " of " +
               cap_name + "; it is not read");
  }
  // Regular files never block; reads go on as ordinary blocking reads.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return CheckedFile(guard.release(), size, shown);
}

}  // namespace

CheckedFile::CheckedFile(int fd, std::uint64_t size, std::filesystem::path path)
    : fd_(fd), size_(size), path_(std::move(path)) {}

CheckedFile::CheckedFile(CheckedFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), size_(other.size_), path_(std::move(other.path_)) {}

CheckedFile& CheckedFile::operator=(CheckedFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    size_ = other.size_;
    path_ = std::move(other.path_);
  }
  return *this;
}

CheckedFile::~CheckedFile() {
  if (fd_ >= 0) ::close(fd_);
}

CheckedFile open_checked_file(const std::filesystem::path& path, std::uint64_t max_bytes,
                              const std::string& what, const std::string& cap_name) {
  if (path.empty()) throw core::InvalidInput(what + ": no path given");
  return open_at(AT_FDCWD, path.string(), path, max_bytes, what, cap_name, true);
}

CheckedFile open_checked_file_in(const std::filesystem::path& directory,
                                 const std::filesystem::path& file, std::uint64_t max_bytes,
                                 const std::string& what, const std::string& cap_name,
                                 const std::string& directory_name) {
  const std::filesystem::path dir = directory.lexically_normal();
  const std::filesystem::path full = (file.is_absolute() ? file : dir / file).lexically_normal();
  if (file.empty() || full.parent_path() != dir || full.filename().empty() ||
      full.filename() == "." || full.filename() == "..") {
    refuse(what, file,
           "not a file directly in " + dir.string() + " (" + directory_name +
               "), the one directory recordings may come from");
  }
  const int dirfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dirfd < 0) {
    refuse(what, full,
           "its directory " + dir.string() + " (" + directory_name +
               ") cannot be opened: " + std::strerror(errno));
  }
  try {
    CheckedFile checked =
        open_at(dirfd, full.filename().string(), full, max_bytes, what, cap_name, false);
    ::close(dirfd);
    return checked;
  } catch (...) {
    ::close(dirfd);
    throw;
  }
}

std::string read_checked_file(const CheckedFile& file, std::uint64_t max_bytes,
                              const std::string& what, const std::string& cap_name) {
  std::string text;
  std::array<char, kReadChunk> chunk{};
  for (off_t at = 0;;) {
    const ssize_t n = ::pread(file.fd(), chunk.data(), chunk.size(), at);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw core::Error(what + " " + file.path().string() +
                        ": read failed: " + std::strerror(errno));
    }
    if (n == 0) return text;
    if (text.size() + static_cast<std::size_t>(n) > max_bytes) {
      refuse(what, file.path(),
             "grew past the " + std::to_string(max_bytes) + " bytes of " + cap_name +
                 " while it was read; it is not read");
    }
    text.append(chunk.data(), static_cast<std::size_t>(n));
    at += n;
  }
}

}  // namespace tofcomp::io
