#include "tests/layers/layer_rules.hpp"

#include <algorithm>
#include <fstream>
#include <regex>

namespace tofcomp::layers {

const LayerRules& project_rules() {
  static const LayerRules kRules{
      {"core", {"core"}},
      {"io", {"core", "io"}},
      {"calibration", {"core", "io", "calibration"}},
      {"hal", {"core", "hal"}},
      {"ipc", {"core", "ipc"}},
      {"client", {"core", "ipc", "client"}},
      {"sim", {"core", "io", "hal", "sim"}},
      {"realtime", {"core", "io", "calibration", "ipc", "realtime"}},
      {"settings", {"core", "io", "hal", "ipc", "sim", "realtime", "settings"}},
      {"daemon",
       {"core", "io", "calibration", "hal", "ipc", "sim", "realtime", "settings", "daemon"}},
      {"cli",
       {"core", "io", "calibration", "hal", "ipc", "client", "sim", "realtime", "settings", "cli"}},
      {"bridges", {"core", "io", "ipc", "client", "bridges"}},
  };
  return kRules;
}

namespace {

bool is_source(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".cpp" || ext == ".hpp" || ext == ".h" || ext == ".cc";
}

}  // namespace

std::vector<LayerViolation> find_layer_violations(const std::filesystem::path& root,
                                                  const LayerRules& rules) {
  // `#include "folder/rest"`: the first path component names the folder.
  static const std::regex kInclude(R"(^\s*#\s*include\s*"([^/"]+)/)");
  std::vector<LayerViolation> found;
  for (const auto& [folder, allowed] : rules) {
    const std::filesystem::path dir = root / folder;
    if (!std::filesystem::is_directory(dir)) continue;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
      if (entry.is_regular_file() && is_source(entry.path())) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      std::ifstream in(file);
      std::string text;
      int line = 0;
      while (std::getline(in, text)) {
        ++line;
        std::smatch m;
        if (!std::regex_search(text, m, kInclude)) continue;
        const std::string to = m[1].str();
        if (rules.count(to) != 0 && allowed.count(to) == 0) {
          found.push_back({std::filesystem::relative(file, root), line, folder, to});
        }
      }
    }
  }
  return found;
}

std::string describe(const LayerViolation& v, const LayerRules& rules) {
  std::string allowed;
  for (const std::string& folder : rules.at(v.from)) {
    allowed += (allowed.empty() ? "" : ", ") + folder;
  }
  return v.file.string() + ":" + std::to_string(v.line) + ": " + v.from + " may not include " +
         v.to + "/ (" + v.from + " may use: " + allowed + ")";
}

}  // namespace tofcomp::layers
