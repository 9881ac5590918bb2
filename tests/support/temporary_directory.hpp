// Test helper: a fresh directory of its own (mkdtemp), removed with everything in it when the
// helper goes, so that runs by different users or in parallel never share a file and a run
// leaves nothing behind.
#pragma once

#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace tofcomp::test {

// Where a test's Unix sockets go: short, because a socket's path holds at most 107 bytes and a
// TMPDIR may be long.
inline const std::filesystem::path kSocketParent = "/tmp";

class TemporaryDirectory {
 public:
  // A directory named `prefix` and six random characters, under `parent`.
  explicit TemporaryDirectory(
      std::string_view prefix = "tofcomp-test",
      const std::filesystem::path& parent = std::filesystem::temp_directory_path()) {
    std::string pattern = (parent / (std::string(prefix) + "-XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("cannot create " + pattern + ": " + std::strerror(errno));
    }
    path_ = pattern;
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  ~TemporaryDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace tofcomp::test
