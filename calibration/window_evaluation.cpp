#include "calibration/window_evaluation.hpp"

#include "core/cramer_rao.hpp"
#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

// Whether each window (starting at starts[i], of length window) holds a range whose flag is set:
// a running count of the flags, two lookups a window.
std::vector<bool> windows_holding_one(const std::vector<bool>& flags,
                                      const std::vector<Eigen::Index>& starts,
                                      Eigen::Index window) {
  std::vector<Eigen::Index> set_before(flags.size() + 1, 0);
  for (std::size_t k = 0; k < flags.size(); ++k) set_before[k + 1] = set_before[k] + (flags[k] ? 1 : 0);
  std::vector<bool> out;
  out.reserve(starts.size());
  for (const Eigen::Index start : starts) {
    const auto begin = static_cast<std::size_t>(start);
    out.push_back(set_before[begin + static_cast<std::size_t>(window)] > set_before[begin]);
  }
  return out;
}

// Whether each window has a range whose bias is extrapolated (beyond the band's junction range).
std::vector<bool> windows_beyond_trained(const core::MeasurementModel& band,
                                         const Compensation& compensation,
                                         const std::vector<Eigen::Index>& starts,
                                         Eigen::Index window) {
  const Eigen::VectorXd& junction = compensation.junction.junction_c;
  std::vector<bool> extrapolated(static_cast<std::size_t>(junction.size()));
  for (Eigen::Index k = 0; k < junction.size(); ++k) {
    extrapolated[static_cast<std::size_t>(k)] = band.extrapolates(junction[k]);
  }
  return windows_holding_one(extrapolated, starts, window);
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

// Keeps the windows that hold no range `counted` excludes; returns how many went.
Eigen::Index keep_counted_windows(core::WindowEstimates& estimates, Eigen::Index window,
                                  const std::vector<bool>& counted) {
  std::vector<bool> excluded(counted.size());
  for (std::size_t k = 0; k < counted.size(); ++k) excluded[k] = !counted[k];
  const std::vector<bool> holds_excluded = windows_holding_one(excluded, estimates.start, window);
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < holds_excluded.size(); ++i) {
    if (!holds_excluded[i]) rows.push_back(static_cast<Eigen::Index>(i));
  }
  const auto left_out = static_cast<Eigen::Index>(estimates.start.size() - rows.size());
  std::vector<Eigen::Index> starts;
  starts.reserve(rows.size());
  for (const Eigen::Index r : rows) starts.push_back(estimates.start[static_cast<std::size_t>(r)]);
  estimates.start = std::move(starts);
  estimates.em_distance = Eigen::VectorXd(estimates.em_distance(rows));
  estimates.em_distance_std = Eigen::VectorXd(estimates.em_distance_std(rows));
  estimates.raw_mean = Eigen::VectorXd(estimates.raw_mean(rows));
  estimates.bias_corrected_mean = Eigen::VectorXd(estimates.bias_corrected_mean(rows));
  return left_out;
}

// The error moments of an evaluation whose estimates, truths and beyond flags are set; none
// (count 0) where every window was left out.
void fill_error_moments(WindowEvaluation& e) {
  if (e.estimates.start.empty()) return;
  e.em = core::error_moments(e.estimates.em_distance, e.truth_mm);
  e.raw = core::error_moments(e.estimates.raw_mean, e.truth_mm);
  e.bias_corrected = core::error_moments(e.estimates.bias_corrected_mean, e.truth_mm);
  e.em_inside_trained = moments_where(e.estimates.em_distance, e.truth_mm, e.beyond_trained, false);
  e.em_beyond_trained = moments_where(e.estimates.em_distance, e.truth_mm, e.beyond_trained, true);
}

// a then b.
Eigen::VectorXd joined(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd out(a.size() + b.size());
  out << a, b;
  return out;
}

}  // namespace

std::vector<WindowEvaluation> evaluate_windows(const MeasuredData& data,
                                               const core::Calibration& calibration,
                                               const Compensation& compensation,
                                               const std::vector<Eigen::Index>& windows,
                                               Eigen::Index stride,
                                               const std::function<void(double)>& progress,
                                               const std::vector<bool>& counted,
                                               const core::MeasurementModel* band) {
  if (!counted.empty() && counted.size() != static_cast<std::size_t>(data.range_mm.size())) {
    throw core::InvalidInput("window evaluation: " + std::to_string(counted.size()) +
                             " flags of what counts for " + std::to_string(data.range_mm.size()) +
                             " ranges");
  }
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
    if (!counted.empty()) e.windows_left_out = keep_counted_windows(e.estimates, e.window, counted);
    e.has_truth = has_truth;
    if (has_truth) {
      const auto count = static_cast<Eigen::Index>(e.estimates.start.size());
      e.truth_mm.resize(count);
      for (Eigen::Index i = 0; i < count; ++i) {
        e.truth_mm[i] =
            data.true_range_mm.segment(e.estimates.start[static_cast<std::size_t>(i)], e.window)
                .mean();
      }
      e.beyond_trained =
          windows_beyond_trained(band ? *band : calibration.model, compensation,
                                 e.estimates.start, e.window);
      fill_error_moments(e);
    }
    out.push_back(std::move(e));
  }
  if (progress) progress(1.0);
  return out;
}

std::vector<WindowEvaluation> pool_window_evaluations(
    const std::vector<std::vector<WindowEvaluation>>& per_beam) {
  if (per_beam.empty()) return {};
  std::vector<WindowEvaluation> pooled = per_beam.front();
  for (std::size_t b = 1; b < per_beam.size(); ++b) {
    if (per_beam[b].size() != pooled.size()) {
      throw core::InvalidInput("pooling window evaluations of different window lengths");
    }
    for (std::size_t w = 0; w < pooled.size(); ++w) {
      WindowEvaluation& p = pooled[w];
      const WindowEvaluation& e = per_beam[b][w];
      if (e.window != p.window) {
        throw core::InvalidInput("pooling window evaluations of different window lengths");
      }
      // Starts index each beam's own ranges: pooled, they only count the windows.
      p.estimates.start.insert(p.estimates.start.end(), e.estimates.start.begin(),
                               e.estimates.start.end());
      p.estimates.em_distance = joined(p.estimates.em_distance, e.estimates.em_distance);
      p.estimates.em_distance_std = joined(p.estimates.em_distance_std, e.estimates.em_distance_std);
      p.estimates.raw_mean = joined(p.estimates.raw_mean, e.estimates.raw_mean);
      p.estimates.bias_corrected_mean =
          joined(p.estimates.bias_corrected_mean, e.estimates.bias_corrected_mean);
      p.windows_left_out += e.windows_left_out;
      p.has_truth = p.has_truth && e.has_truth;
      p.truth_mm = joined(p.truth_mm, e.truth_mm);
      p.beyond_trained.insert(p.beyond_trained.end(), e.beyond_trained.begin(),
                              e.beyond_trained.end());
    }
  }
  for (WindowEvaluation& p : pooled) {
    if (p.has_truth) fill_error_moments(p);
  }
  return pooled;
}

}  // namespace tofcomp::calibration
