// What `tofcomp train` prints after training in the field (calibration/field_training.hpp):
// per beam what was still, the fit, and how its constant was fixed.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/field_training.hpp"

namespace tofcomp::cli {

nlohmann::json field_training_json(const calibration::FieldTraining& t);
std::string field_training_text(const calibration::FieldTraining& t);

}  // namespace tofcomp::cli
