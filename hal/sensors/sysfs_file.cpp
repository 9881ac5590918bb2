#include "hal/sensors/sysfs_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <system_error>

namespace tofcomp::hal {

SysfsRead read_sysfs_file(const std::filesystem::path& file) {
  SysfsRead result;
  int fd = -1;
  do {
    fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) {
    result.error = errno;
    return result;
  }
  std::array<char, 4096> buffer{};
  // sysfs attributes are at most one page; stop there in case a path points at something else.
  while (result.content.size() < 2 * buffer.size()) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      result.error = errno;
      break;
    }
    if (n == 0) break;
    result.content.append(buffer.data(), static_cast<std::size_t>(n));
  }
  ::close(fd);
  return result;
}

ReadingValidity validity_of_errno(int error) {
  return error == ENOENT || error == ENODEV || error == ENXIO ? ReadingValidity::Missing
                                                              : ReadingValidity::ReadError;
}

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

std::string_view trim(std::string_view text) {
  constexpr std::string_view kBlanks = " \t\r\n";
  const auto first = text.find_first_not_of(kBlanks);
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(kBlanks);
  return text.substr(first, last - first + 1);
}

}  // namespace tofcomp::hal
