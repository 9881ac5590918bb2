// The text and JSON forms of the residual tests (core/residual_diagnosis.hpp): the evidence
// `tofcomp diagnose` prints beside its model search (cli/search_format.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

// [{effect, test, covariate, statistic, p_value, z, significant, search_effect}]: search_effect
// is the effect of the model search's grammar the test is evidence for (core::effect_name of its
// label: "temperature-dependent weights" for the test of the mode weights), null for serial
// dependence, a symptom of any of them.
nlohmann::json to_json(const core::Diagnosis& d);

std::string diagnosis_text(const core::Diagnosis& d);

}  // namespace tofcomp::cli
