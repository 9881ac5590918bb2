// The text and JSON forms of a fleet recalibration (calibration/recording_batch.hpp): each
// recording's whole outcome as written beside its calibration, and the one-row-per-recording
// table `tofcomp calibrate-dir` prints.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "calibration/recording_batch.hpp"

namespace tofcomp::cli {

// {recording, status, error, warnings, seconds, calibration_file, training (as train --json
//  prints it, or null), search (as diagnose --json prints it, or null), search_error, named}.
// status: "calibrated", "calibrated, not diagnosed" (the search could not run) or "failed".
nlohmann::json recording_json(const calibration::RecordingOutcome& outcome,
                              const calibration::ModelSearchOptions& options,
                              const std::string& calibration_file);

// The fields of the table from recording_json's document: {recording, status, error, ranges,
// junction_c: [min, max], structure, junction_from, named, mae_over_cramer_rao: {window: ratio}
// (the deployed model's held-out d̂), seconds, calibration_file}.
nlohmann::json recording_row(const nlohmann::json& recording);

// One line per row, in the rows' order, and a line counting the calibrated and the failed.
std::string batch_table_text(const std::vector<nlohmann::json>& rows,
                             const std::vector<Eigen::Index>& windows);

}  // namespace tofcomp::cli
