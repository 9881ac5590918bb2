// A directory tree under the system's temporary directory for the sysfs backends' tests
// (hwmon, w1): files are written into it as the kernel would lay them out, and the whole tree
// is removed when the test ends.
#pragma once

#include <filesystem>
#include <fstream>
#include <string_view>

#include "tests/support/temporary_directory.hpp"

namespace tofcomp::hal::testing {

class TemporaryTree {
 public:
  const std::filesystem::path& root() const { return directory_.path(); }

  // Writes `contents` to root()/relative, creating the directories on the way.
  std::filesystem::path write(const std::filesystem::path& relative, std::string_view contents) {
    const auto file = root() / relative;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << contents;
    return file;
  }

 private:
  tofcomp::test::TemporaryDirectory directory_{"tofcomp-hal-sensors"};
};

}  // namespace tofcomp::hal::testing
