#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::io {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what, int error) {
  throw core::Error(file + ": " + what + ": " + std::strerror(error));
}

void write_all(int fd, std::string_view data, const std::string& file) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(file, "cannot write", errno);
    }
    data.remove_prefix(static_cast<std::size_t>(n));
  }
}

void fsync_directory(const std::filesystem::path& dir, const std::string& file) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) fail(file, "cannot open its directory to sync it", errno);
  const int rc = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (rc != 0) fail(file, "cannot sync its directory", error);
}

}  // namespace

void write_file_atomically(const std::string& file, std::string_view contents) {
  const std::filesystem::path target(file);
  std::string temporary = (target.parent_path() / ("." + target.filename().string() + ".XXXXXX"));
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) fail(file, "cannot create a temporary file beside it", errno);
  try {
    write_all(fd, contents, file);
    if (::fchmod(fd, 0644) != 0) fail(file, "cannot set permissions", errno);
    if (::fsync(fd) != 0) fail(file, "cannot sync", errno);
    if (::close(fd) != 0) fail(file, "cannot close", errno);
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  if (::rename(temporary.c_str(), file.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    fail(file, "cannot rename the temporary file over it", error);
  }
  fsync_directory(target.parent_path(), file);
}

void write_file_atomically(const std::string& file,
                           const std::function<void(std::ostream&)>& write) {
  std::ostringstream out;
  write(out);
  write_file_atomically(file, out.str());
}

}  // namespace tofcomp::io
