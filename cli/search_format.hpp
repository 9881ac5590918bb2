// The text and JSON forms of the model search (calibration/model_search.hpp): what
// `tofcomp diagnose` prints first, the headline (what was named, kept, the held-out error of d̂
// before and after against the Cramér–Rao bound), then each step's ranked candidates.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/model_search.hpp"

namespace tofcomp::cli {

// {alpha, block, blocks, candidates_per_step, steps: [{kept, critical_t, critical_p,
//  family_wise_p, candidates: [...], errors: [...]}], best: {effect, parameter, covariate, form, term} | null, kept: [...],
//  mae_mm: {base: {window: mm}, final: {...}}, mae_factor: {window: base / final},
//  cramer_rao_mae_mm: {window: mm}, mae_over_cramer_rao: {base: {window: ratio}, final: {...}}}:
//  base is the trained model, final the model with the kept terms, both on held-out windows
nlohmann::json to_json(const calibration::ModelSearchResult& search,
                       const calibration::ModelSearchOptions& options);

// The terms' effect names, joined by ", " (empty for none; "nothing" for none with the second).
std::string effect_names(const std::vector<core::Term>& terms);
std::string effect_names_or_nothing(const std::vector<core::Term>& terms);
// The terms as described (core::Term::describe), a JSON array.
nlohmann::json term_descriptions(const std::vector<core::Term>& terms);
// The name of what was kept ("none" when nothing was).
std::string kept_names(const calibration::ModelSearchResult& search);

std::string search_text(const calibration::ModelSearchResult& search,
                        const calibration::ModelSearchOptions& options);

}  // namespace tofcomp::cli
