#include "core/estimators.hpp"

#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/extended_em.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

// The window loop shared by both noise models: `fit` runs EM testing on [first, first + window)
// from a warm start; `offset` is each range's common mode offset Σ_i π_i μ_i, which the centred
// mean of y − Hθ̂ leaves out.
template <typename Fit>
WindowEstimates window_loop(const Eigen::Ref<const Eigen::VectorXd>& y,
                            const Eigen::Ref<const Eigen::VectorXd>& bias,
                            const Eigen::VectorXd& offset, Eigen::Index window, Eigen::Index stride,
                            const Fit& fit) {
  require_same_length(y.size(), "y", bias.size(), "H theta");
  require_same_length(y.size(), "y", offset.size(), "mode offsets");
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
    const auto offset_window = offset.segment(first, window);
    const EmTestResult result = fit(first, warm_start);
    warm_start = result.distance;
    out.start.push_back(first);
    out.em_distance[w] = result.distance;
    out.em_distance_std[w] = result.distance_std;
    out.raw_mean[w] = y_window.mean();
    out.bias_corrected_mean[w] = (y_window - bias_window - offset_window).mean();
  }
  return out;
}

// Σ_i π_{s_k,i} (μ_i + shift_ki) at each range: the mean of the extended mixture's modes in the
// range's noise state (under a chain π is the modes' share over the data it was fitted on).
Eigen::VectorXd common_offsets(const Eigen::Ref<const Eigen::VectorXi>& state,
                               const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                               const ExtendedMixture& noise) {
  const int modes = noise.modes.modes();
  if (mode_shift.size() > 0 && mode_shift.cols() != modes) {
    throw InvalidInput("mode shifts have " + std::to_string(mode_shift.cols()) + " columns for " +
                       std::to_string(modes) + " modes");
  }
  Eigen::VectorXd out(state.size());
  for (Eigen::Index k = 0; k < state.size(); ++k) {
    if (state[k] < 0 || state[k] >= noise.states()) {
      throw InvalidInput("noise state " + std::to_string(state[k]) + " of range " +
                         std::to_string(k) + " is not one of the mixture's " +
                         std::to_string(noise.states()));
    }
    double sum = 0.0;
    for (int i = 0; i < modes; ++i) {
      const double shift = mode_shift.size() > 0 ? mode_shift(k, i) : 0.0;
      sum += noise.weight(state[k], i) * (noise.modes.mean[i] + shift);
    }
    out[k] = sum;
  }
  return out;
}

}  // namespace

WindowEstimates estimate_windows(const Eigen::Ref<const Eigen::VectorXd>& y,
                                 const Eigen::Ref<const Eigen::VectorXd>& bias,
                                 const MixtureParameters& mixture, Eigen::Index window,
                                 Eigen::Index stride, const EmTestOptions& options) {
  mixture.validate();
  const Eigen::VectorXd offset = Eigen::VectorXd::Constant(y.size(), mixture.mean_offset());
  return window_loop(y, bias, offset, window, stride,
                     [&](Eigen::Index first, std::optional<double> warm) {
                       return test_em(y.segment(first, window), bias.segment(first, window),
                                      mixture, options, warm);
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
  noise.validate();
  const Eigen::VectorXd offset = common_offsets(state, mode_shift, noise);
  return window_loop(
      y, bias, offset, window, stride, [&](Eigen::Index first, std::optional<double> warm) {
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
