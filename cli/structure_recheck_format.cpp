#include "cli/structure_recheck_format.hpp"

#include <fmt/format.h>

#include "cli/search_format.hpp"

namespace tofcomp::cli {

nlohmann::json to_json(const calibration::StructureRecheck& r) {
  return {{"first", r.first},
          {"first_modes", r.first_modes},
          {"bias_terms", term_descriptions(r.bias_terms)},
          {"again", r.again.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.again)},
          {"again_modes",
           r.again.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.again_modes)},
          {"kept_first", term_descriptions(r.kept_first)},
          {"first_search_paused", r.first_search_paused},
          {"searched_again", r.searched_again},
          {"kept_again", term_descriptions(r.kept_again)},
          {"chosen", r.chosen ? "again" : "first"},
          {"error", r.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.error)}};
}

std::string structure_recheck_text(const calibration::StructureRecheck& r) {
  std::string out = fmt::format(
      "the structure re-checked: training chose {} and the search {} {}; ", r.first,
      r.first_search_paused ? "paused at its first term on the bias had kept" : "kept",
      effect_names_or_nothing(r.kept_first));
  if (!r.error.empty()) return out + r.error + "; the first structure stands\n";
  out += fmt::format("on the ranges less the bias of {} the structure search chooses {}",
                     effect_names_or_nothing(r.bias_terms), r.again);
  if (!r.searched_again) return out + ": the same, the first stands\n";
  out += fmt::format("; trained at it, the search keeps {}: {}\n",
                     effect_names_or_nothing(r.kept_again),
                     r.chosen ? "that structure is the start reported"
                              : "no term on the bias, the first structure stands");
  return out;
}

}  // namespace tofcomp::cli
