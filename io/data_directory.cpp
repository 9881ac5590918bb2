#include "io/data_directory.hpp"

#include <system_error>

#include "core/error.hpp"

namespace tofcomp::io {

std::filesystem::path data_directory() {
  std::error_code error;
  const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) {
    throw core::Error("cannot find the program's data directory: /proc/self/exe: " +
                      error.message());
  }
  return (binary.parent_path() / TOFCOMP_DATA_FROM_BINDIR).lexically_normal();
}

}  // namespace tofcomp::io
