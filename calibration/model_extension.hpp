// Closing the loop: the extension of Eq. 8 for the effect the residual diagnosis named, fitted
// on the training part and judged on held-out data (core/model_extension.hpp):
//   time drift                  + γ · time (h)                       one more design column
//   heating hysteresis          + γ · dt^j/dt (°C/min)               one more design column
//   mode persistence            a Markov chain over the modes        forward-backward E-step
//   temperature-dependent weights  π_i per junction-temperature bin   closed-form M-step
//   temperature-dependent spread   σ_i² per junction-temperature bin  closed-form M-step
//   outliers                    + a uniform component over the span  closed-form M-step
//   one more lasing mode        M + 1 modes (the paper's EM)
//   serial dependence           (a symptom) each extension that acts in time — mode persistence,
//                               time drift, heating hysteresis — and the best on held-out data
// Every fit starts from the paper's model trained on the same data. The held-out comparison
// uses the test part's smoothed junction temperature and its known distance: the held-out
// log-likelihood of y − d under both models, and the error of the window estimate d̂ (§6, §8.4)
// for each window length. The extension is kept when it raises the held-out log-likelihood and
// cuts the mean absolute error of d̂, averaged over the window lengths, by at least 1 %
// (kMinimumMaeFactor): an extension that leaves d̂ as it was is not worth carrying into the
// daemon, however much better it explains the noise.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "calibration/training.hpp"
#include "core/estimators.hpp"
#include "core/model_extension.hpp"

namespace tofcomp::calibration {

inline constexpr double kMinimumMaeFactor = 1.01;

struct WindowComparison {
  Eigen::Index window = 0;
  core::ErrorMoments before;       // d̂ of the paper's model on the held-out part
  core::ErrorMoments after;        // d̂ of the extended model
  double cramer_rao_mae_mm = 0.0;  // the bound of d under the paper's modes (core/cramer_rao.hpp)
};

struct ExtensionReport {
  core::EffectKind named = core::EffectKind::SerialDependence;   // what the diagnosis named
  core::EffectKind effect = core::EffectKind::SerialDependence;  // what the extension models
  std::string model;                                             // one sentence
  std::vector<std::pair<std::string, double>> parameters;
  core::Calibration calibration;  // the paper's model plus the extension, trained on `train`
  double held_out_log_likelihood_before = 0.0;
  double held_out_log_likelihood_after = 0.0;
  std::vector<WindowComparison> errors;
  bool kept = false;

  double held_out_log_likelihood_gain() const {
    return held_out_log_likelihood_after - held_out_log_likelihood_before;
  }
  // MAE before / after, averaged over the window lengths.
  double mean_absolute_error_factor() const;
};

// Fits the extension for `named` on `train` and judges it on `test` (which must carry the true
// distance). Windows longer than the test part are left out. Throws core::Error when a fit fails.
ExtensionReport evaluate_extension(core::EffectKind named, const MeasuredData& train,
                                   const MeasuredData& test, const TrainSettings& settings,
                                   const std::vector<Eigen::Index>& windows, Eigen::Index stride);

}  // namespace tofcomp::calibration
