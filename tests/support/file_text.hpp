// The whole of a file as text (its bytes as they are; an empty string when it cannot be read:
// the tests compare what they read with what they expect).
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace tofcomp::testing {

inline std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace tofcomp::testing
