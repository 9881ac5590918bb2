#include "calibration/window_evaluation.hpp"

#include "core/cramer_rao.hpp"

namespace tofcomp::calibration {

std::vector<WindowEvaluation> evaluate_windows(const MeasuredData& data,
                                               const core::Calibration& calibration,
                                               const Compensation& compensation,
                                               const std::vector<Eigen::Index>& windows,
                                               Eigen::Index stride,
                                               const std::function<void(double)>& progress) {
  bool has_truth = data.range_mm.size() > 0;
  for (const bool known : data.has_true_range) has_truth = has_truth && known;
  // One range's information about d: the same for every window length.
  const double range_information =
      core::range_fisher_information(calibration.model.mixture, kRangeResolutionMm);
  std::vector<WindowEvaluation> out;
  for (std::size_t w = 0; w < windows.size(); ++w) {
    if (progress) progress(static_cast<double>(w) / static_cast<double>(windows.size()));
    WindowEvaluation e;
    e.window = windows[w];
    e.cramer_rao_mae_mm = core::cramer_rao_mae_mm(range_information, e.window);
    e.estimates =
        calibration.extension
            ? core::estimate_windows(
                  data.range_mm, compensation.bias_mm,
                  calibration.extension->extended_mixture.bin_of(compensation.junction.junction_c),
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
    }
    out.push_back(std::move(e));
  }
  if (progress) progress(1.0);
  return out;
}

}  // namespace tofcomp::calibration
