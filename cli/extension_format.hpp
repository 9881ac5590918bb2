// The text and JSON forms of a diagnosis and of the extension judged on held-out data
// (`tofcomp diagnose`; the JSON is also what `diagnose --report` renders).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/model_extension.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

// findings: [{effect, test, covariate, statistic, p_value, z, significant}], named.
nlohmann::json to_json(const core::Diagnosis& d);
// {effect, named, model, parameters {name: value}, held_out_log_likelihood_before/after/gain,
//  kept, mae_factor, errors: [{window, before, after, mae_factor}]}.
nlohmann::json to_json(const calibration::ExtensionReport& e);

std::string diagnosis_text(const core::Diagnosis& d);
std::string extension_text(const calibration::ExtensionReport& e);

}  // namespace tofcomp::cli
