// The text and JSON forms of the junction's re-check after the model search kept a term
// (calibration/junction_recheck.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/junction_recheck.hpp"

namespace tofcomp::cli {

// {first: "ranges" | "case_log" (the junction training took), from_ranges: {rise_k,
//  time_constant_s, kept: [...]}, from_case_log: {...}, common_ranges, from_ranges_per_range,
//  from_case_log_per_range, chosen: "ranges" | "case_log", error | null}
nlohmann::json to_json(const calibration::JunctionRecheck& recheck);
std::string junction_recheck_text(const calibration::JunctionRecheck& recheck);

}  // namespace tofcomp::cli
