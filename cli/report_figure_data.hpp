// The data behind the report's figures that `tofcomp evaluate --figures` does not write
// (cli/figure_data.hpp writes the others), as CSV files into a directory:
//   glr.csv             Algorithm 2 per candidate basis: GLR, BIC, held-out likelihood (Fig. 9-10)
//   em_test_trace.csv   d̂ after each EM testing iteration on one test set (Fig. 14)
//   em_test_cost.csv    measured time of EM testing against the number of samples, for two
//                       model orders (Fig. 15)
//   moments.csv         per window length and estimator, the error moments (Fig. 18-19)
//   diagnosis_samples.csv  the whole record under the trained model the residual tests ran under,
//                       with what the tests computed of each range (their evidence figures)
// The renderer (cli/report/) draws these values; it computes none of them.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "calibration/compensation.hpp"
#include "calibration/window_evaluation.hpp"
#include "core/calibration.hpp"
#include "core/em_train.hpp"
#include "core/gaussian_mixture.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

// Junction temperatures t̂^j and y − d of a training set.
struct TrainingResiduals {
  Eigen::VectorXd junction_c;
  Eigen::VectorXd y_minus_d;
};

struct GlrOrders {
  int polynomial = 16;
  int fourier = 8;
};

// Fig. 9-10: Algorithm 2 (core::select_model) over polynomial orders 1..orders.polynomial (Eq. 9,
// Legendre form) and Fourier orders 1..orders.fourier (Eq. 11) with the fundamental f0 = 1 / (2 ×
// the span of the training temperatures), so that order 1 is one monotone half period over the
// data. Returns what was run (candidates, f0, seconds) for the report. `progress` gets the
// fraction done.
nlohmann::json write_glr_data(const std::filesystem::path& directory,
                              const TrainingResiduals& training, GlrOrders orders,
                              const core::EmTrainOptions& em,
                              const std::function<void(double)>& progress);

// Fig. 14: EM testing (§6, Eq. 22-23) with its trace on the first `samples` ranges of the test
// part (all of them when fewer), started as the paper does from d̂ = 1ᵀy / K.
nlohmann::json write_em_test_trace(const std::filesystem::path& directory,
                                   const calibration::MeasuredData& test,
                                   const calibration::Compensation& compensation,
                                   const core::MixtureParameters& mixture, Eigen::Index samples);

// Fig. 15: the wall time of EM testing (the bias H θ̂ from t̂^j, then `steps` iterations of
// Eq. 22-23) on the first K test ranges, K over a grid up to the test part's length, for a model
// of each Fourier order, each trained on `training`. The best of a few repetitions. An order
// whose training fails (a singular normal matrix on data spanning few temperatures) is left out,
// its reason in the returned "left_out".
nlohmann::json write_em_test_cost(const std::filesystem::path& directory,
                                  const TrainingResiduals& training,
                                  const calibration::MeasuredData& test,
                                  const calibration::Compensation& compensation,
                                  const std::vector<int>& fourier_orders, double f0_per_c,
                                  const core::EmTrainOptions& em, int steps);

// Fig. 18-19: the error moments of the three estimators of §8.4 for each window length.
void write_error_moments(const std::filesystem::path& directory,
                         const std::vector<calibration::WindowEvaluation>& evaluations);

// The residual tests' evidence figures: diagnosis_samples.csv, the whole record `measured` under
// `trained`, the calibration the tests in `diagnosis` ran under, range by range: the time, the
// time since the last power-on, y, d, t̂^j, the bias Hθ̂, the residual y − d − Hθ̂, its most
// probable mode under the mixture (Eq. 18 with the true distance) and e = y − d − Hθ̂ − μ̂ of that
// mode as the tests computed them, and the junction's heating rate in °C/min as the tests used it
// (core::local_rate over ±kHeatingRateHalfWindowS). No fitted effect: what the search fitted is in
// the figures of its terms (cli/search_figure_data.hpp). Returns {heating_rate_half_window_s}.
nlohmann::json write_diagnosis_samples(const std::filesystem::path& directory,
                                       const calibration::MeasuredData& measured,
                                       const core::Calibration& trained,
                                       const core::Diagnosis& diagnosis);

}  // namespace tofcomp::cli
