// A directory tree under the system's temporary directory for the sysfs backends' tests
// (hwmon, w1): files are written into it as the kernel would lay them out, and the whole tree
// is removed when the test ends.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <string_view>

namespace tofcomp::hal::testing {

class TemporaryTree {
 public:
  TemporaryTree() {
    std::random_device random;
    root_ = std::filesystem::temp_directory_path() /
            ("tofcomp-hal-sensors-" + std::to_string(::getpid()) + "-" + std::to_string(random()) +
             "-" + std::to_string(random()));
    std::filesystem::create_directories(root_);
  }
  ~TemporaryTree() {
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  }
  TemporaryTree(const TemporaryTree&) = delete;
  TemporaryTree& operator=(const TemporaryTree&) = delete;

  const std::filesystem::path& root() const { return root_; }

  // Writes `contents` to root()/relative, creating the directories on the way.
  std::filesystem::path write(const std::filesystem::path& relative, std::string_view contents) {
    const auto file = root_ / relative;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << contents;
    return file;
  }

 private:
  std::filesystem::path root_;
};

}  // namespace tofcomp::hal::testing
