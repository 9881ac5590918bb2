// What `tofcomp test` prints (calibration/beam_scores.hpp): the windows pooled over the beams
// scored, then each beam's ranges, those set apart as not still, and d̂'s MAE over the bound.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/beam_scores.hpp"

namespace tofcomp::cli {

nlohmann::json beam_scores_json(const calibration::BeamScores& scores);
std::string beam_scores_text(const calibration::BeamScores& scores);

}  // namespace tofcomp::cli
