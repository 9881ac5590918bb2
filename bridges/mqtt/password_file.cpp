// Reading the broker password from its file, with the checks of a secret.
#include "bridges/mqtt/password_file.hpp"

#include <sys/stat.h>

#include <cstdint>

#include "core/error.hpp"
#include "io/checked_file.hpp"

namespace tofcomp::bridges::mqtt {

std::string read_password_file(const std::filesystem::path& file) {
  const io::CheckedFile checked = io::open_checked_file(file, kMaxPasswordFileBytes,
                                                        "password file", "the largest password file");
  struct stat info {};
  if (::fstat(checked.fd(), &info) != 0) {
    throw core::InvalidInput("password file " + file.string() + ": cannot be examined");
  }
  if ((info.st_mode & S_IROTH) != 0) {
    throw core::InvalidInput("password file " + file.string() +
                             ": readable by every user (mode o+r); make it 0600 or 0640");
  }
  const std::string text = io::read_checked_file(checked, kMaxPasswordFileBytes, "password file",
                                                 "the largest password file");
  std::string password = text.substr(0, text.find('\n'));
  if (!password.empty() && password.back() == '\r') password.pop_back();
  if (password.empty()) {
    throw core::InvalidInput("password file " + file.string() + ": its first line is empty");
  }
  return password;
}

}  // namespace tofcomp::bridges::mqtt
