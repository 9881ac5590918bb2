// tofcomp diagnose --report DIR: the HTML report of a diagnosis. This file's one job is the
// data: it computes what is behind each figure and writes it, with the diagnosis JSON, into
// DIR/data/, then runs the renderer (cli/report_renderer.hpp), which draws DIR/figures/*.png and
// writes DIR/index.html: the search's headline first (what was kept, the held-out MAE factor of
// d̂, MAE over the Cramér–Rao bound before and after), the figure of each term the search kept,
// drawn with the values the final calibration holds (cli/search_figure_data.hpp), the paper's
// figures, and the residual tests as evidence.
//
// The held-out split is the diagnosis's own: split_time(measured, 0.5); the paper's model is
// trained on the first part (its thermal fit checked on the second, Fig. 8; its EM trace,
// Fig. 13) and every figure of testing is drawn on the second part (Fig. 3, 4, 11, 12, 14, 16-19).
// Algorithm 2 (Fig. 9-10) and the cost of EM testing (Fig. 15) use the training part.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "calibration/model_search.hpp"
#include "calibration/training.hpp"
#include "cli/report_figure_data.hpp"

namespace tofcomp::cli {

struct ReportSettings {
  // Fig. 16-17 and the error table; lengths longer than the held-out part are left out.
  std::vector<Eigen::Index> windows{200, 400, 800};
  // Fig. 18-19: the moments against the window length.
  std::vector<Eigen::Index> moment_windows{50, 100, 200, 300, 400, 600, 800, 1000};
  Eigen::Index stride = 1;  // samples between window starts (1: every window, as Fig. 16)
  // Fig. 9-10: polynomial orders 1..max (the paper selected N = 16) and Fourier orders 1..max
  // (beyond 8 the normal matrix of Eq. 19 is singular on a few degrees of junction temperature).
  GlrOrders glr_orders{16, 8};
  Eigen::Index convergence_samples = 4000;     // Fig. 14 (the paper's test set: 4000)
  std::vector<int> cost_fourier_orders{2, 8};  // Fig. 15: two model orders
  int cost_steps = 10;                         // Fig. 15: EM test steps timed
};

// Makes DIR and DIR/data and finds the renderer and a Python that runs it: what the report
// needs that the diagnosis cannot give, checked before the diagnosis's long work. Throws
// core::Error naming the directory, or what the renderer lacks.
void check_report_possible(const std::string& directory);

// What `tofcomp diagnose` found, as the report shows it.
struct DiagnosisOutcome {
  const nlohmann::json& json;                    // what `tofcomp diagnose --json` prints
  const core::Calibration& trained;              // the paper's model the search started from
  const calibration::ModelSearchResult& search;  // its calibration: the kept terms, fitted
  const core::Diagnosis& tests;                  // the residual tests, run under `trained`
};

// Writes the report of a diagnosis on `measured` into `directory`, creating it. The figures of the
// kept terms are drawn on the whole record under the search's final calibration, those of the
// residual tests on the whole record under the trained model, with the modes and residuals the
// tests ran on. Throws core::Error naming the directory when it cannot be made, and whatever
// training, testing or the renderer throws. Progress on stderr when show_progress.
void write_diagnosis_report(const std::string& directory, const calibration::MeasuredData& measured,
                            const calibration::TrainSettings& settings,
                            const DiagnosisOutcome& diagnosis, const ReportSettings& report,
                            bool show_progress);

}  // namespace tofcomp::cli
