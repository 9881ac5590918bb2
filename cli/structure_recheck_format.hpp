// The text and JSON forms of the structure's re-check after the model search kept a term on the
// bias (calibration/structure_recheck.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/trained_search.hpp"

namespace tofcomp::cli {

// {first, first_modes, bias_terms: [...], again | null, again_modes | null, kept_first: [...],
//  searched_again, kept_again: [...], chosen: "first" | "again", error | null}
nlohmann::json to_json(const calibration::StructureRecheck& recheck);
std::string structure_recheck_text(const calibration::StructureRecheck& recheck);

}  // namespace tofcomp::cli
