// The text and JSON forms of the choices training made from the data: the Kalman filter's noise
// levels (core/kalman_noise_fit.hpp) and the structure of Eq. 8 (core/structure_search.hpp),
// each with its evidence.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/training.hpp"

namespace tofcomp::cli {

nlohmann::json to_json(const core::KalmanNoiseFit& fit);
nlohmann::json to_json(const core::StructureChoice& choice);
// Both, under "kalman_noise" and "structure" (each null when given by the user).
nlohmann::json choices_json(const calibration::Training& training);

std::string kalman_noise_text(const core::KalmanNoiseFit& fit);
std::string structure_text(const core::StructureChoice& choice);
// Both, or a line saying each was given.
std::string choices_text(const calibration::Training& training);

}  // namespace tofcomp::cli
