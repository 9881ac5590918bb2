// The offline pipeline of §8 over measured data, shared by the subcommands: thermal
// identification (§3.2), junction temperature (§3.3), EM training (§5) into a calibration, and
// the window estimators of §8.4 on test data.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cli/measured_data.hpp"
#include "core/em_train.hpp"
#include "core/estimators.hpp"
#include "core/residual_diagnosis.hpp"
#include "core/thermal_identification.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::cli {

struct ThermalFitSettings {
  core::DatasheetThermalData datasheet;  // Algorithm 1: the start of the fit
  core::ThermalParameterMask free;       // what the prediction-error method fits
  double ambient_fallback_c = 22.0;      // when the data carry no ambient_c
};

struct ThermalFit {
  core::ThermalParameters algorithm1;
  core::PemResult pem;
  bool has_held_out = false;
  double held_out_paper_fit_percent = 0.0;  // Eq. 26 on the held-out part
  double held_out_nrmse_fit_percent = 0.0;
  Eigen::VectorXd held_out_time_s, held_out_measured_c, held_out_predicted_c;
};

// Algorithm 1, then the prediction-error fit on `train`, then the fit of the identified model
// driven by the held-out part's inputs (§8.1), when held_out has temperature readings.
ThermalFit fit_thermal(const MeasuredData& train, const MeasuredData* held_out,
                       const ThermalFitSettings& settings);

struct TrainSettings {
  ThermalFitSettings thermal;
  core::ThermalNoise noise;
  std::string basis = "polynomial:4";
  core::EmTrainOptions em;
};

struct Training {
  io::Calibration calibration;
  ThermalFit thermal;
  JunctionEstimate junction;
  core::EmTrainResult em;
};

// The whole of training on data with a known distance; the calibration's provenance names
// the data set. With held_out, the thermal model's fit is also reported on it (§8.1).
// Throws core::Error with the reason when any stage fails.
Training train_calibration(const MeasuredData& data, const TrainSettings& settings,
                           const MeasuredData* held_out = nullptr);

// The bias H θ̂ at each range of `data` under a calibration, from the smoothed junction
// temperature.
struct Compensation {
  JunctionEstimate junction;
  Eigen::VectorXd bias_mm;
};
// With an extension (core/model_extension.hpp) the bias also carries its covariate term.
Compensation compensate(const MeasuredData& data, const io::Calibration& calibration);

// The noise ranges are compensated under: the extension's when the calibration has one, else
// the paper's mixture.
core::ExtendedMixture noise_of(const io::Calibration& calibration);

// log p(y − d | calibration) over the ranges of data with a known distance: the held-out
// criterion of an extension.
double held_out_log_likelihood(const MeasuredData& data, const io::Calibration& calibration,
                               const Compensation& compensation);

// The residual diagnosis (core/residual_diagnosis.hpp) of data with a known distance under a
// calibration; the junction's heating rate is its smoothed estimate's slope over ±30 s.
core::Diagnosis diagnose(const MeasuredData& data, const io::Calibration& calibration);

struct WindowEvaluation {
  Eigen::Index window = 0;
  core::WindowEstimates estimates;
  bool has_truth = false;
  Eigen::VectorXd truth_mm;           // mean true distance of each window
  core::ErrorMoments em;              // d̂
  core::ErrorMoments raw;             // ȳ
  core::ErrorMoments bias_corrected;  // mean of y − Hθ̂
};

// The three estimators on every window of each length (d̂ under the calibration's noise, extended
// or not) (stride apart), and their error moments
// where the data carry the true distance (Fig. 16-19). `progress` gets the fraction done.
std::vector<WindowEvaluation> evaluate_windows(const MeasuredData& data,
                                               const io::Calibration& calibration,
                                               const Compensation& compensation,
                                               const std::vector<Eigen::Index>& windows,
                                               Eigen::Index stride,
                                               const std::function<void(double)>& progress = {});

}  // namespace tofcomp::cli
