#include "calibration/model_extension.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "calibration/compensation.hpp"
#include "calibration/window_evaluation.hpp"
#include "core/em_train.hpp"
#include "core/error.hpp"
#include "core/extended_em.hpp"
#include "core/warm_up.hpp"

namespace tofcomp::calibration {
namespace {

constexpr int kTemperatureBins = 4;
constexpr double kOutlierStartWeight = 0.02;
constexpr double kOutlierTrimFraction = 0.02;

// What a fit produces: the design's θ and the extension.
struct Fit {
  Eigen::VectorXd theta;
  core::ModelExtension extension;
  std::string model;
  std::vector<std::pair<std::string, double>> parameters;
};

core::Covariate covariate_of(core::EffectKind effect) {
  if (effect == core::EffectKind::TimeDrift) return core::Covariate::TimeHours;
  if (effect == core::EffectKind::HeatingHysteresis) return core::Covariate::HeatingRateCPerMinute;
  if (effect == core::EffectKind::WarmUp) return core::Covariate::WarmUp;
  return core::Covariate::None;
}

// The modes of the residuals once the tails are cut off: the start of the outlier fit, so that
// the paper's EM's broad mode (which held the outliers) does not survive into it.
core::MixtureParameters trimmed_quantile_modes(const Eigen::VectorXd& residual, int modes) {
  std::vector<double> sorted(residual.data(), residual.data() + residual.size());
  std::sort(sorted.begin(), sorted.end());
  const auto cut =
      static_cast<std::size_t>(kOutlierTrimFraction * static_cast<double>(sorted.size()));
  const std::vector<double> core_values(sorted.begin() + static_cast<std::ptrdiff_t>(cut),
                                        sorted.end() - static_cast<std::ptrdiff_t>(cut));
  core::MixtureParameters m;
  m.mean.resize(modes);
  m.variance.resize(modes);
  m.weight = Eigen::VectorXd::Constant(modes, 1.0 / modes);
  const std::size_t n = core_values.size();
  for (int i = 0; i < modes; ++i) {
    const auto begin =
        core_values.begin() + static_cast<std::ptrdiff_t>(n * static_cast<std::size_t>(i) /
                                                          static_cast<std::size_t>(modes));
    const auto end =
        core_values.begin() + static_cast<std::ptrdiff_t>(n * static_cast<std::size_t>(i + 1) /
                                                          static_cast<std::size_t>(modes));
    const double count = static_cast<double>(end - begin);
    const double mean = std::accumulate(begin, end, 0.0) / count;
    double spread = 0.0;
    for (auto it = begin; it != end; ++it) spread += (*it - mean) * (*it - mean);
    m.mean[i] = mean;
    m.variance[i] = std::max(spread / count, 1e-6);
  }
  return m;
}

// The start of the extended EM for the named effect, from the paper's fit.
core::ExtendedMixture start_mixture(core::EffectKind effect, const core::MixtureParameters& base,
                                    const Eigen::VectorXd& residual,
                                    const Eigen::VectorXd& junction_c) {
  core::ExtendedMixture m = core::without_extensions(base);
  const int modes = base.modes();
  switch (effect) {
    case core::EffectKind::ModePersistence:
      m.transition = 0.5 * Eigen::MatrixXd::Identity(modes, modes) +
                     0.5 * Eigen::VectorXd::Ones(modes) * base.weight.transpose();
      break;
    case core::EffectKind::TemperatureDependentWeights:
      m.bin_edges_c = core::quantile_edges(junction_c, kTemperatureBins);
      m.bin_weight = Eigen::VectorXd::Ones(kTemperatureBins) * base.weight.transpose();
      break;
    case core::EffectKind::TemperatureDependentSpread:
      m.bin_edges_c = core::quantile_edges(junction_c, kTemperatureBins);
      m.bin_variance = Eigen::VectorXd::Ones(kTemperatureBins) * base.variance.transpose();
      break;
    case core::EffectKind::Outliers:
      m.modes = trimmed_quantile_modes(residual, modes);
      m.outlier_weight = kOutlierStartWeight;
      m.outlier_density = 1.0 / std::max(residual.maxCoeff() - residual.minCoeff(), 1.0);
      break;
    default:
      break;
  }
  return m;
}

std::string describe(const core::ModelExtension& e, int base_modes) {
  switch (e.effect) {
    case core::EffectKind::TimeDrift:
      return "Eq. 8 + gamma * time (h): a drift of the range with time";
    case core::EffectKind::HeatingHysteresis:
      return "Eq. 8 + gamma * dt^j/dt (°C/min): a bias that depends on heating or cooling";
    case core::EffectKind::WarmUp:
      return fmt::format(
          "Eq. 8 + gamma * exp(-t_on / tau), tau = {:.0f} s: a transient after each power-on (t_on "
          "the time since it; tau by the profile likelihood)",
          e.time_constant_s);
    case core::EffectKind::ModePersistence:
      return "Eq. 8 with the lasing mode a Markov chain (transition matrix A) instead of "
             "independent draws";
    case core::EffectKind::TemperatureDependentWeights:
      return fmt::format("Eq. 8 with the mode weights pi_i per junction-temperature bin ({} bins)",
                         e.extended_mixture.bins());
    case core::EffectKind::TemperatureDependentSpread:
      return fmt::format(
          "Eq. 8 with the mode variances sigma_i^2 per junction-temperature bin ({} "
          "bins)",
          e.extended_mixture.bins());
    case core::EffectKind::Outliers:
      return "Eq. 8 plus a uniform outlier component over the residuals' span";
    case core::EffectKind::ExtraMode:
      return fmt::format("Eq. 8 with {} lasing modes instead of {}",
                         e.extended_mixture.modes.modes(), base_modes);
    case core::EffectKind::SerialDependence:
      break;
  }
  return "Eq. 8";
}

std::vector<std::pair<std::string, double>> parameters_of(const core::ModelExtension& e) {
  std::vector<std::pair<std::string, double>> out;
  const core::ExtendedMixture& n = e.extended_mixture;
  if (e.covariate != core::Covariate::None) {
    out.emplace_back(std::string("gamma_mm_per_") + core::covariate_name(e.covariate),
                     e.covariate_mm);
  }
  if (e.covariate == core::Covariate::WarmUp) out.emplace_back("tau_s", e.time_constant_s);
  for (Eigen::Index i = 0; i < n.transition.rows(); ++i) {
    out.emplace_back(fmt::format("stay_probability_mode{}", i + 1), n.transition(i, i));
  }
  for (Eigen::Index b = 0; b < n.bin_edges_c.size(); ++b) {
    out.emplace_back(fmt::format("bin_edge{}_c", b + 1), n.bin_edges_c[b]);
  }
  for (Eigen::Index b = 0; b < n.bin_weight.rows(); ++b) {
    for (Eigen::Index i = 0; i < n.bin_weight.cols(); ++i) {
      out.emplace_back(fmt::format("weight_bin{}_mode{}", b + 1, i + 1), n.bin_weight(b, i));
    }
  }
  for (Eigen::Index b = 0; b < n.bin_variance.rows(); ++b) {
    for (Eigen::Index i = 0; i < n.bin_variance.cols(); ++i) {
      out.emplace_back(fmt::format("std_bin{}_mode{}_mm", b + 1, i + 1),
                       std::sqrt(n.bin_variance(b, i)));
    }
  }
  if (n.outlier_weight > 0.0) {
    out.emplace_back("outlier_weight", n.outlier_weight);
    out.emplace_back("outlier_span_mm", 1.0 / n.outlier_density);
  }
  if (e.effect == core::EffectKind::ExtraMode) {
    for (int i = 0; i < n.modes.modes(); ++i) {
      out.emplace_back(fmt::format("mean_mode{}_mm", i + 1), n.modes.mean[i]);
      out.emplace_back(fmt::format("std_mode{}_mm", i + 1), std::sqrt(n.modes.variance[i]));
      out.emplace_back(fmt::format("weight_mode{}", i + 1), n.modes.weight[i]);
    }
  }
  return out;
}

// The warm-up's τ between the neighbours of the best point of the grid, by a golden-section
// search in log τ for the largest `log_likelihood_at(τ)` (which fits at τ and keeps the best).
template <typename LogLikelihoodAt>
void refine_time_constant(double best_on_grid, LogLikelihoodAt&& log_likelihood_at) {
  constexpr int kSteps = 12;  // the bracket shrinks to 0.618^12 ≈ 0.3 % of its log-width
  const auto& grid = core::kWarmUpTimeConstantsS;
  const auto at = std::find(grid.begin(), grid.end(), best_on_grid);
  if (at == grid.end()) return;
  double lo = std::log(at == grid.begin() ? grid.front() : *(at - 1));
  double hi = std::log(at + 1 == grid.end() ? grid.back() : *(at + 1));
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
  double fa = log_likelihood_at(std::exp(a)), fb = log_likelihood_at(std::exp(b));
  for (int step = 0; step < kSteps; ++step) {
    if (fa >= fb) {
      hi = b, b = a, fb = fa;
      a = hi - ratio * (hi - lo);
      fa = log_likelihood_at(std::exp(a));
    } else {
      lo = a, a = b, fa = fb;
      b = lo + ratio * (hi - lo);
      fb = log_likelihood_at(std::exp(b));
    }
  }
}

// Fits the extension for one effect (not serial dependence) on the training part.
Fit fit_extension(core::EffectKind effect, const MeasuredData& train, const Training& base,
                  const TrainSettings& settings) {
  const core::Calibration& c = base.calibration;
  const Eigen::VectorXd& junction = base.junction.junction_c;
  const Eigen::VectorXd y = train.range_mm - train.true_range_mm;
  Eigen::MatrixXd h = c.model.basis.design_matrix(junction);
  Eigen::VectorXd theta = c.model.theta;
  Fit fit;
  fit.extension.effect = effect;
  fit.extension.covariate = covariate_of(effect);
  if (effect == core::EffectKind::ExtraMode) {
    core::EmTrainOptions options = settings.em;
    options.modes = c.model.mixture.modes() + 1;
    options.record_trace = false;
    const core::EmTrainResult em = core::train_em(h, y, options);
    fit.theta = em.theta;
    fit.extension.extended_mixture = core::without_extensions(em.mixture);
  } else {
    const core::ExtendedMixture start =
        start_mixture(effect, c.model.mixture, y - c.model.bias(junction), junction);
    const Eigen::VectorXi bin = start.bin_of(junction);
    const bool has_covariate = fit.extension.covariate != core::Covariate::None;
    if (has_covariate) {
      h.conservativeResize(Eigen::NoChange, h.cols() + 1);
      theta.conservativeResize(theta.size() + 1);
      theta[theta.size() - 1] = 0.0;
    }
    const Eigen::VectorXd time_since_power_on_s = train.time_since_power_on();
    const core::CovariateInputs inputs{train.range_time_s, junction, time_since_power_on_s};
    // The closed-form EM for one τ of the warm-up (which the other covariates ignore), kept when
    // its likelihood is the best so far.
    std::optional<core::ExtendedEmResult> best;
    const auto consider = [&](double tau) {
      if (has_covariate) {
        h.col(h.cols() - 1) = core::covariate_values(fit.extension.covariate, inputs, tau);
      }
      core::ExtendedEmResult em = core::train_extended_em(h, y, bin, theta, start);
      const double log_likelihood = em.log_likelihood;
      if (!best || log_likelihood > best->log_likelihood) {
        best = std::move(em);
        fit.extension.time_constant_s = tau;
      }
      return log_likelihood;
    };
    if (fit.extension.covariate == core::Covariate::WarmUp) {
      // τ maximizes the profile likelihood: the grid, then a golden-section search in log τ
      // between the best grid point's neighbours.
      for (const double tau : core::kWarmUpTimeConstantsS) consider(tau);
      refine_time_constant(fit.extension.time_constant_s, consider);
    } else {
      consider(0.0);
    }
    fit.theta = best->theta;
    fit.extension.extended_mixture = best->model;
    if (has_covariate) {
      fit.extension.covariate_mm = fit.theta[fit.theta.size() - 1];
      fit.theta.conservativeResize(fit.theta.size() - 1);
    }
  }
  fit.model = describe(fit.extension, c.model.mixture.modes());
  fit.parameters = parameters_of(fit.extension);
  return fit;
}

std::vector<WindowComparison> compare_windows(const MeasuredData& test,
                                              const core::Calibration& before,
                                              const Compensation& before_compensation,
                                              const core::Calibration& after,
                                              const Compensation& after_compensation,
                                              const std::vector<Eigen::Index>& windows,
                                              Eigen::Index stride) {
  std::vector<Eigen::Index> usable;
  for (const Eigen::Index w : windows) {
    if (w <= test.range_mm.size()) usable.push_back(w);
  }
  if (usable.empty()) {
    throw core::InvalidInput(fmt::format("the held-out part has {} ranges: fewer than any window",
                                         test.range_mm.size()));
  }
  const auto b = evaluate_windows(test, before, before_compensation, usable, stride);
  const auto a = evaluate_windows(test, after, after_compensation, usable, stride);
  std::vector<WindowComparison> out;
  for (std::size_t i = 0; i < usable.size(); ++i) {
    out.push_back({usable[i], b[i].em, a[i].em, b[i].cramer_rao_mae_mm});
  }
  return out;
}

// The report of one candidate extension against the paper's model.
ExtensionReport judge(core::EffectKind named, const Fit& fit, const Training& base,
                      const MeasuredData& test, const std::vector<Eigen::Index>& windows,
                      Eigen::Index stride) {
  ExtensionReport r;
  r.named = named;
  r.effect = fit.extension.effect;
  r.model = fit.model;
  r.parameters = fit.parameters;
  r.calibration = base.calibration;
  r.calibration.model.theta = fit.theta;
  r.calibration.model.mixture = fit.extension.extended_mixture.modes;
  r.calibration.extension = fit.extension;
  r.calibration.provenance.notes += std::string("; extended for ") + core::effect_name(r.effect);

  const Compensation before = compensate(test, base.calibration);
  const Compensation after = compensate(test, r.calibration);
  r.held_out_log_likelihood_before = held_out_log_likelihood(test, base.calibration, before);
  r.held_out_log_likelihood_after = held_out_log_likelihood(test, r.calibration, after);
  r.errors = compare_windows(test, base.calibration, before, r.calibration, after, windows, stride);
  r.kept =
      r.held_out_log_likelihood_gain() > 0.0 && r.mean_absolute_error_factor() >= kMinimumMaeFactor;
  return r;
}

}  // namespace

double ExtensionReport::mean_absolute_error_factor() const {
  double before = 0.0, after = 0.0;
  for (const auto& e : errors) {
    before += e.before.mean_absolute_error;
    after += e.after.mean_absolute_error;
  }
  return after > 0.0 ? before / after : 1.0;
}

ExtensionReport evaluate_extension(core::EffectKind named, const MeasuredData& train,
                                   const MeasuredData& test, const TrainSettings& settings,
                                   const std::vector<Eigen::Index>& windows, Eigen::Index stride) {
  train.require_true_ranges();
  test.require_true_ranges();
  const Training base = train_calibration(train, settings);
  if (named != core::EffectKind::SerialDependence) {
    return judge(named, fit_extension(named, train, base, settings), base, test, windows, stride);
  }
  // A symptom: each extension that acts in time, the best held-out likelihood kept.
  std::optional<ExtensionReport> best;
  for (const core::EffectKind candidate :
       {core::EffectKind::ModePersistence, core::EffectKind::TimeDrift,
        core::EffectKind::HeatingHysteresis, core::EffectKind::WarmUp}) {
    ExtensionReport r =
        judge(named, fit_extension(candidate, train, base, settings), base, test, windows, stride);
    if (!best || r.held_out_log_likelihood_gain() > best->held_out_log_likelihood_gain()) {
      best = std::move(r);
    }
  }
  return *best;
}

}  // namespace tofcomp::calibration
