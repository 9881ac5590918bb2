// The layers of docs/architecture.md as a table, and the check of a source tree against it: each
// `#include "folder/..."` of a product folder must name a folder that folder may use. Layers
// point one way (core ← io ← calibration ← realtime ← settings ← daemon, cli); hal, ipc and sim
// sit beside them. Tests, benchmarks and fuzzers may include anything and are not checked.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace tofcomp::layers {

// For each product folder, the folders its sources may include (itself among them).
using LayerRules = std::map<std::string, std::set<std::string>>;

// The project's rules (the table in docs/architecture.md).
const LayerRules& project_rules();

struct LayerViolation {
  std::filesystem::path file;  // relative to the root
  int line = 0;
  std::string from;  // the folder the file is in
  std::string to;    // the folder its include names
};

// Every wrong-way include under `root`, in path order. Only the folders named in `rules` are
// read; an include of a folder not in `rules` (a system header in quotes, say) is not checked.
std::vector<LayerViolation> find_layer_violations(const std::filesystem::path& root,
                                                  const LayerRules& rules);

// "core/bad.hpp:3: core may not include daemon/ (core may use: core)".
std::string describe(const LayerViolation& violation, const LayerRules& rules);

}  // namespace tofcomp::layers
