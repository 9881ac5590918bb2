// tofcomp diagnose --report DIR: the HTML report of a diagnosis. This file's one job is the
// data: it computes what is behind each of the paper's figures on held-out data and writes it,
// with the diagnosis JSON, into DIR/data/, then runs the renderer (cli/report_renderer.hpp),
// which draws DIR/figures/*.png and writes DIR/index.html.
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

// Writes the report of `diagnosis` (the JSON that `tofcomp diagnose --json` prints) on
// `measured` into `directory`, creating it. `diagnosed` is the calibration the diagnosis ran
// under and `residual_diagnosis` the diagnosis itself: the figures of the findings are drawn on the
// whole record under it, with the modes and residuals the tests ran on. Throws core::Error naming
// the directory when it cannot be made, and whatever training, testing or the renderer throws.
// Progress on stderr when show_progress.
void write_diagnosis_report(const std::string& directory, const calibration::MeasuredData& measured,
                            const calibration::TrainSettings& settings,
                            const nlohmann::json& diagnosis, const core::Calibration& diagnosed,
                            const core::Diagnosis& residual_diagnosis, const ReportSettings& report,
                            bool show_progress);

}  // namespace tofcomp::cli
