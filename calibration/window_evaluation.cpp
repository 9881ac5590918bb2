#include "calibration/window_evaluation.hpp"

#include "core/cramer_rao.hpp"

namespace tofcomp::calibration {
namespace {

// Whether window i (starting at start, of length window) has a range whose bias is extrapolated:
// a running count over the ranges' extrapolation flags.
std::vector<bool> windows_beyond_trained(const core::Calibration& calibration,
                                         const Compensation& compensation,
                                         const std::vector<Eigen::Index>& starts,
                                         Eigen::Index window) {
  const Eigen::VectorXd& junction = compensation.junction.junction_c;
  std::vector<Eigen::Index> extrapolated_before(static_cast<std::size_t>(junction.size()) + 1, 0);
  for (Eigen::Index k = 0; k < junction.size(); ++k) {
    extrapolated_before[static_cast<std::size_t>(k) + 1] =
        extrapolated_before[static_cast<std::size_t>(k)] +
        (calibration.model.extrapolates(junction[k]) ? 1 : 0);
  }
  std::vector<bool> out;
  out.reserve(starts.size());
  for (const Eigen::Index start : starts) {
    const auto begin = static_cast<std::size_t>(start);
    out.push_back(extrapolated_before[begin + static_cast<std::size_t>(window)] >
                  extrapolated_before[begin]);
  }
  return out;
}

// The error moments of the windows whose flag equals `beyond`.
core::ErrorMoments moments_where(const Eigen::VectorXd& estimates, const Eigen::VectorXd& truth,
                                 const std::vector<bool>& flags, bool beyond) {
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < flags.size(); ++i) {
    if (flags[i] == beyond) rows.push_back(static_cast<Eigen::Index>(i));
  }
  if (rows.empty()) return {};
  return core::error_moments(estimates(rows), truth(rows));
}

}  // namespace

std::vector<WindowEvaluation> evaluate_windows(const MeasuredData& data,
                                               const core::Calibration& calibration,
                                               const Compensation& compensation,
                                               const std::vector<Eigen::Index>& windows,
                                               Eigen::Index stride,
                                               const std::function<void(double)>& progress) {
  bool has_truth = data.range_mm.size() > 0;
  for (const bool known : data.has_true_range) has_truth = has_truth && known;
  // One range's information about d: the same for every window length. The trained modes hold
  // the rounding's variance (Sheppard's correction, core/gaussian_mixture.hpp); the bound rounds
  // the modes before it, or it would count the rounding twice (4-8 % too lenient on modes of
  // σ 0.7-0.9 mm: foreign-5's 0.062 mm at 200 ranges where its truth file gives 0.0575).
  const double range_information = core::range_fisher_information(
      core::modes_before_rounding(calibration.model.mixture, kRangeResolutionMm),
      kRangeResolutionMm);
  std::vector<WindowEvaluation> out;
  for (std::size_t w = 0; w < windows.size(); ++w) {
    if (progress) progress(static_cast<double>(w) / static_cast<double>(windows.size()));
    WindowEvaluation e;
    e.window = windows[w];
    e.cramer_rao_mae_mm = core::cramer_rao_mae_mm(range_information, e.window);
    e.estimates =
        calibration.extension
            ? core::estimate_windows(data.range_mm, compensation.bias_mm,
                                     compensation.noise_state, compensation.mode_shift,
                                     calibration.extension->extended_mixture, e.window, stride)
            : core::estimate_windows(data.range_mm, compensation.bias_mm, calibration.model.mixture,
                                     e.window, stride);
    e.has_truth = has_truth;
    if (has_truth) {
      const auto count = static_cast<Eigen::Index>(e.estimates.start.size());
      e.truth_mm.resize(count);
      for (Eigen::Index i = 0; i < count; ++i) {
        e.truth_mm[i] =
            data.true_range_mm.segment(e.estimates.start[static_cast<std::size_t>(i)], e.window)
                .mean();
      }
      e.em = core::error_moments(e.estimates.em_distance, e.truth_mm);
      e.raw = core::error_moments(e.estimates.raw_mean, e.truth_mm);
      e.bias_corrected = core::error_moments(e.estimates.bias_corrected_mean, e.truth_mm);
      const std::vector<bool> beyond =
          windows_beyond_trained(calibration, compensation, e.estimates.start, e.window);
      e.em_inside_trained = moments_where(e.estimates.em_distance, e.truth_mm, beyond, false);
      e.em_beyond_trained = moments_where(e.estimates.em_distance, e.truth_mm, beyond, true);
    }
    out.push_back(std::move(e));
  }
  if (progress) progress(1.0);
  return out;
}

}  // namespace tofcomp::calibration
