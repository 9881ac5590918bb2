// Fleet recalibration offline: the recordings of many scanners, each calibrated (§3, §5, as
// `tofcomp train`) and diagnosed (the model search of model_search.hpp, as `tofcomp diagnose`)
// on its own, several at once. A recording that cannot be read or trained keeps its error in its
// outcome and the others go on; nothing of one recording depends on the others or on how many
// run at once.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibration/model_search.hpp"
#include "calibration/trained_search.hpp"
#include "calibration/training.hpp"

namespace tofcomp::calibration {

// The recordings a batch reads: regular files with this extension (the interchange CSV).
inline constexpr const char* kRecordingExtension = ".csv";
// The most recordings one batch takes; a directory with more is refused, not half-calibrated.
inline constexpr std::size_t kMaxBatchRecordings = 10000;

// The recordings of a directory (not its subdirectories), sorted by name. Throws
// core::InvalidInput naming the directory when it cannot be listed, holds no recording, or holds
// more than kMaxBatchRecordings.
std::vector<std::filesystem::path> recordings_in(const std::filesystem::path& directory);

struct BatchSettings {
  TrainSettings training;      // its `threads` is set by the batch
  ModelSearchOptions search;   // its `threads` is set by the batch
  int beam = 0;
  int jobs = 0;  // recordings calibrated at once; 0: one per core
};

struct RecordingOutcome {
  std::filesystem::path recording;
  std::vector<std::string> warnings;  // the reader's (unknown columns)
  std::string error;                  // why it could not be read or trained; empty when it was
  std::optional<Training> training;
  std::string search_error;  // why the model search could not run; the training still stands
  std::optional<ModelSearchResult> search;
  std::optional<JunctionRecheck> junction_recheck;  // when it ran (calibration/junction_recheck.hpp)
  std::optional<StructureRecheck> structure_recheck;  // when it ran (calibration/structure_recheck.hpp)
  double seconds = 0.0;  // wall clock of this recording's work

  bool calibrated() const { return training.has_value(); }
  // The calibration to deploy: the search's, with the terms it kept, when it kept any; else
  // the training's. Only when calibrated().
  const core::Calibration& calibration() const;
};

// Called when a recording starts and when it ends, with its index in `recordings`: from the
// thread that runs it, one call at a time. `finished` receives the outcome to keep or drop.
using RecordingStarted = std::function<void(std::size_t index)>;
using RecordingFinished = std::function<void(std::size_t index, RecordingOutcome&& outcome)>;

// Calibrates and diagnoses each recording. The threads a recording's own searches use are the
// batch's threads shared among the recordings that run at once, which changes no result (the
// searches give their serial results on any number of threads).
void calibrate_recordings(const std::vector<std::filesystem::path>& recordings,
                          const BatchSettings& settings, const RecordingStarted& started,
                          const RecordingFinished& finished);

}  // namespace tofcomp::calibration
