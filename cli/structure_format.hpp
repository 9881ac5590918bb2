// The text and JSON forms of the choices training made from the data: the Kalman filter's noise
// levels (core/kalman_noise_fit.hpp), the structure of Eq. 8 (core/structure_search.hpp) and the
// junction's dynamics (calibration/junction_dynamics.hpp), each with its evidence.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "calibration/training.hpp"

namespace tofcomp::cli {

nlohmann::json to_json(const core::KalmanNoiseFit& fit);
nlohmann::json to_json(const core::StructureChoice& choice);
nlohmann::json to_json(const calibration::JunctionDynamicsFit& fit);
// All three, under "kalman_noise", "structure" and "junction_dynamics" (each null when given
// by the user or not run).
nlohmann::json choices_json(const calibration::Training& training);

std::string kalman_noise_text(const core::KalmanNoiseFit& fit);
std::string structure_text(const core::StructureChoice& choice);
std::string junction_dynamics_text(const calibration::JunctionDynamicsFit& fit);
// All three, or a line saying each was given.
std::string choices_text(const calibration::Training& training);

// The model `diagnose` searches from: Eq. 8's basis and modes and, when training chose the
// structure (`choice` not null), the best held-out log-likelihood per range at each number of
// modes, so that a mode the structure took in (a mode the data carry beyond the expected ones)
// shows there and not among the search's terms.
std::string trained_model_text(const core::Calibration& calibration,
                               const core::StructureChoice* choice);
nlohmann::json trained_model_json(const core::Calibration& calibration,
                                  const core::StructureChoice* choice);

}  // namespace tofcomp::cli
