// The text and JSON forms of the residual tests (core/residual_diagnosis.hpp): the evidence
// `tofcomp diagnose` prints beside its model search (cli/search_format.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

// [{effect, test, covariate, statistic, p_value, z, significant}]
nlohmann::json to_json(const core::Diagnosis& d);

std::string diagnosis_text(const core::Diagnosis& d);

}  // namespace tofcomp::cli
