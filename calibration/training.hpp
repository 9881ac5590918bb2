// The whole of training (§3 and §5) on measured data with a known distance: thermal fit, the
// Kalman filter's noise levels, smoothed junction temperature, the structure of Eq. 8 (basis and
// number of modes) and EM training of Eq. 8 into a calibration.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibration/gross_errors.hpp"
#include "calibration/junction_dynamics.hpp"
#include "calibration/junction_estimate.hpp"
#include "calibration/measured_data.hpp"
#include "calibration/thermal_fit.hpp"
#include "core/calibration.hpp"
#include "core/em_train.hpp"
#include "core/kalman_noise_fit.hpp"
#include "core/structure_search.hpp"

namespace tofcomp::calibration {

// Where training takes the junction's dynamics from.
enum class JunctionSource {
  CaseLog,                // the case-log fit's
  RangesWhereTheyReject,  // the ranges' answer where their blocks' t-test rejects the case log's
  // The ranges' answer wherever its posterior is above the case log's, tested or not: the
  // alternative the junction re-check judges on held-out ranges (calibration/junction_recheck.hpp).
  Ranges,
};

struct TrainSettings {
  ThermalFitSettings thermal;
  // The junction filter's noise levels (§3.3). Absent: chosen from the case log by the
  // innovations' likelihood (core/kalman_noise_fit.hpp), starting from core::ThermalNoise's
  // LMS 200 levels, which stay for any level the log does not determine.
  std::optional<core::ThermalNoise> kalman_noise;
  // H(.) as named by calibration/basis_spec.hpp, and the number of lasing modes. Absent: chosen
  // from the data by held-out likelihood (core/structure_search.hpp).
  std::optional<std::string> basis;
  std::optional<int> modes;
  core::EmTrainOptions em;  // the final fit's options (em.modes is set from `modes` or the search)
  core::StructureSearchOptions search;
  // Where the junction's own dynamics (P·R1, R1·C1) come from (calibration/junction_dynamics.hpp).
  // Only with the datasheet-prior thermal fit; the paper's prediction-error fit (--free) keeps
  // what it identified.
  JunctionSource junction_source = JunctionSource::RangesWhereTheyReject;
  JunctionDynamicsOptions junction_dynamics;
  int threads = 0;  // the structure search's fits run at once; 0: one per core
  // A structure already chosen from these data, its evidence kept (calibration/
  // structure_recheck.hpp chooses it again on the ranges less the bias of the terms the model
  // search kept): training takes it as the search's choice and does not search again.
  std::optional<core::StructureChoice> structure_chosen;
};

struct Training {
  core::Calibration calibration;
  ThermalFit thermal;
  std::optional<core::KalmanNoiseFit> kalman_noise_fit;  // when the levels were chosen from the log
  SmoothedJunction junction;  // at every range, gross errors included
  // The ranges Eq. 8 was not fitted on (calibration/gross_errors.hpp); the calibration carries
  // their share as its outlier component.
  GrossErrors gross_errors;
  std::optional<core::StructureChoice> structure;  // when basis or modes were chosen
  std::optional<JunctionDynamicsFit> junction_dynamics;  // when completed from the ranges
  // The thermal network the calibration carries: the thermal fit's, with the junction's
  // dynamics from the ranges when they replaced it.
  core::ThermalParameters thermal_parameters;
  bool structure_not_chosen = false;  // asked for, but too few ranges: the paper's structure
  // The modes the final fit emptied and dropped from the search's choice (calibration/final_fit.hpp).
  std::vector<std::string> final_fit_dropped_modes;
  core::EmTrainResult em;
};

// Progress of training's long stages: a share in [0, 1] and what runs.
using TrainingProgress = std::function<void(double share, const std::string& stage)>;

// A stage of a longer job's progress: its shares mapped onto [from, from + span] of `progress`,
// its stages named after `prefix` (nothing when `progress` is empty).
TrainingProgress progress_part(const TrainingProgress& progress, double from, double span,
                               const std::string& prefix);

// The whole of training on data with a known distance; the calibration's provenance names
// the data set. With held_out, the thermal model's fit is also reported on it (§8.1).
// Throws core::Error with the reason when any stage fails.
Training train_calibration(const MeasuredData& data, const TrainSettings& settings,
                           const MeasuredData* held_out = nullptr,
                           const TrainingProgress& progress = {});

// The structure training chooses (basis and modes, core/structure_search.hpp, as
// train_calibration runs it with `settings`), on y − d − offset_mm at the junction `trained`
// ended with and over the ranges it fitted Eq. 8 on (gross errors left out). offset_mm: one value
// per range of `data`. Throws core::InvalidInput when training would not choose (a basis and
// modes given, or too few ranges), core::Error when the search fails.
core::StructureChoice choose_structure_on(const MeasuredData& data, const TrainSettings& settings,
                                          const Training& trained,
                                          const Eigen::Ref<const Eigen::VectorXd>& offset_mm,
                                          const TrainingProgress& progress = {});

}  // namespace tofcomp::calibration
