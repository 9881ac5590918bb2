// Loads a twin scenario from YAML (config/scenarios/*.yaml; the keys are documented in
// docs/scenarios.md). Unknown keys and out-of-range values are errors naming the file and key.
#pragma once

#include <string>

#include "sim/scenario.hpp"

namespace tofcomp::sim {

Scenario load_scenario_file(const std::string& file);
// The same for a scenario's text; `source` names it in errors, and a `base:` in it is taken
// from the directory of `source`.
Scenario parse_scenario_yaml(const std::string& text, const std::string& source);

}  // namespace tofcomp::sim
