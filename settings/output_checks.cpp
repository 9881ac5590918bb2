#include "settings/output_checks.hpp"

namespace tofcomp::settings {

std::string socket_path_problem(const std::filesystem::path& path) {
  if (path.native().size() <= kMaxSocketPathBytes) return "";
  return "is " + std::to_string(path.native().size()) +
         " bytes long once resolved; a Unix socket path has at most " +
         std::to_string(kMaxSocketPathBytes);
}

std::string shm_name_problem(const std::string& name) {
  if (name.size() >= 2 && name.size() <= kMaxShmNameBytes + 1 && name.front() == '/' &&
      name.find('/', 1) == std::string::npos && name.find('\0') == std::string::npos) {
    return "";
  }
  return "must be a shared-memory name like \"/tofcompd\" (one leading /, no other, at most " +
         std::to_string(kMaxShmNameBytes) + " characters after it), not \"" + name + "\"";
}

}  // namespace tofcomp::settings
