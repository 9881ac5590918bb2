#include "core/estimators.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/extended_em.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

// The window loop shared by both noise models: `fit` runs EM testing on [first, first + window)
// from a warm start.
template <typename Fit>
WindowEstimates window_loop(const Eigen::Ref<const Eigen::VectorXd>& y,
                            const Eigen::Ref<const Eigen::VectorXd>& bias, Eigen::Index window,
                            Eigen::Index stride, const Fit& fit) {
  require_same_length(y.size(), "y", bias.size(), "H theta");
  if (window < 1 || window > y.size()) {
    std::ostringstream msg;
    msg << "window length " << window << " must be between 1 and the " << y.size()
        << " samples available";
    throw InvalidInput(msg.str());
  }
  if (stride < 1) throw InvalidInput("window stride must be at least 1");

  const Eigen::Index count = (y.size() - window) / stride + 1;
  WindowEstimates out;
  out.window = window;
  out.start.reserve(static_cast<std::size_t>(count));
  out.em_distance.resize(count);
  out.em_distance_std.resize(count);
  out.raw_mean.resize(count);
  out.bias_corrected_mean.resize(count);
  std::optional<double> warm_start;
  for (Eigen::Index w = 0; w < count; ++w) {
    const Eigen::Index first = w * stride;
    const auto y_window = y.segment(first, window);
    const auto bias_window = bias.segment(first, window);
    const EmTestResult result = fit(first, warm_start);
    warm_start = result.distance;
    out.start.push_back(first);
    out.em_distance[w] = result.distance;
    out.em_distance_std[w] = result.distance_std;
    out.raw_mean[w] = y_window.mean();
    out.bias_corrected_mean[w] = (y_window - bias_window).mean();
  }
  return out;
}

}  // namespace

WindowEstimates estimate_windows(const Eigen::Ref<const Eigen::VectorXd>& y,
                                 const Eigen::Ref<const Eigen::VectorXd>& bias,
                                 const MixtureParameters& mixture, Eigen::Index window,
                                 Eigen::Index stride, const EmTestOptions& options) {
  return window_loop(y, bias, window, stride, [&](Eigen::Index first, std::optional<double> warm) {
    return test_em(y.segment(first, window), bias.segment(first, window), mixture, options, warm);
  });
}

WindowEstimates estimate_windows(const Eigen::Ref<const Eigen::VectorXd>& y,
                                 const Eigen::Ref<const Eigen::VectorXd>& bias,
                                 const Eigen::Ref<const Eigen::VectorXi>& state,
                                 const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                                 const ExtendedMixture& noise, Eigen::Index window,
                                 Eigen::Index stride, const EmTestOptions& options) {
  require_same_length(y.size(), "y", state.size(), "noise states");
  const bool shifted = mode_shift.size() > 0;
  if (shifted) require_same_length(y.size(), "y", mode_shift.rows(), "mode shifts");
  return window_loop(y, bias, window, stride, [&](Eigen::Index first, std::optional<double> warm) {
    return test_extended_em(
        y.segment(first, window), bias.segment(first, window), state.segment(first, window),
        shifted ? Eigen::MatrixXd(mode_shift.middleRows(first, window)) : Eigen::MatrixXd(0, 0),
        noise, options, warm);
  });
}

ErrorMoments error_moments(const Eigen::Ref<const Eigen::VectorXd>& estimates,
                           const Eigen::Ref<const Eigen::VectorXd>& truth) {
  require_same_length(estimates.size(), "estimates", truth.size(), "true distances");
  if (estimates.size() == 0) throw InvalidInput("error moments need at least one estimate");
  require_finite(estimates, "estimates");
  require_finite(truth, "true distances");
  const Eigen::ArrayXd error = (estimates - truth).array();
  const Eigen::ArrayXd absolute = error.abs();
  const double n = static_cast<double>(error.size());
  ErrorMoments m;
  m.count = error.size();
  m.mean_error = error.mean();
  m.error_variance = (error - m.mean_error).square().sum() / n;
  m.mean_absolute_error = absolute.mean();
  m.absolute_error_variance = (absolute - m.mean_absolute_error).square().sum() / n;
  m.rmse = std::sqrt(error.square().mean());
  return m;
}

}  // namespace tofcomp::core
