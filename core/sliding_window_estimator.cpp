#include "core/sliding_window_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/extended_em.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// A run of outliers restarts the window when the outlier component alone would give one this
// rarely per range.
constexpr double kFalseRestartChance = 1e-7;

}  // namespace

SlidingWindowEstimator::SlidingWindowEstimator(MixtureParameters mixture,
                                               SlidingWindowOptions options)
    : SlidingWindowEstimator(without_extensions(mixture), options) {}

SlidingWindowEstimator::SlidingWindowEstimator(ExtendedMixture extended_mixture,
                                               SlidingWindowOptions options, bool mode_shifts)
    : extended_mixture_(std::move(extended_mixture)),
      shifted_(mode_shifts),
      options_(options),
      detector_(options.change) {
  extended_mixture_.validate();
  extended_ = extended_mixture_.has_extension() || shifted_;
  chain_ = extended_mixture_.transition.size() > 0;
  if (options_.window < 1 || options_.min_samples < 1 || options_.min_samples > options_.window) {
    std::ostringstream msg;
    msg << "sliding window of " << options_.window << " with min_samples " << options_.min_samples
        << ": need 1 <= min_samples <= window";
    throw InvalidInput(msg.str());
  }
  if (options_.refreshes < 0) {
    throw InvalidInput("sliding window: refreshes " + std::to_string(options_.refreshes) +
                       " must be >= 0");
  }
  ring_.resize(options_.window);
  ring_bin_ = Eigen::VectorXi::Zero(options_.window);
  ordered_.resize(options_.window);
  ordered_bin_.resize(options_.window);
  zeros_ = Eigen::VectorXd::Zero(options_.window);
  terms_.resize(static_cast<std::size_t>(options_.window));
  const int m = extended_mixture_.modes.modes();
  const double log_inlier = std::log1p(-extended_mixture_.outlier_weight);
  log_outlier_ =
      extended_mixture_.outlier_weight > 0.0
          ? std::log(extended_mixture_.outlier_weight * extended_mixture_.outlier_density)
          : -INFINITY;
  for (int b = 0; b < extended_mixture_.states(); ++b) {
    // Without an extension these are the mixture's own vectors: the same arithmetic as ever.
    Eigen::VectorXd weight = extended_mixture_.modes.weight;
    Eigen::VectorXd variance = extended_mixture_.modes.variance;
    for (int i = 0; i < m; ++i) {
      weight[i] = extended_mixture_.weight(b, i);
      variance[i] = extended_mixture_.variance(b, i);
    }
    precision_.push_back(variance.cwiseInverse());
    inverse_std_.push_back(precision_.back().cwiseSqrt());
    log_prior_.push_back(weight.array().log() - 0.5 * variance.array().log());
    log_weight_.push_back(weight.array().log());
    log_density_shift_.push_back(
        (log_inlier - 0.5 * (2.0 * std::numbers::pi * variance.array()).log()).matrix());
  }
  if (chain_) slot_prior_.resize(options_.window, m);
  if (shifted_) {
    ring_shift_ = Eigen::MatrixXd::Zero(options_.window, m);
    ordered_shift_.resize(options_.window, m);
  }
  if (extended_mixture_.outlier_weight > 0.0) {
    // The run of outliers whose chance under the model, ε^n, is below 1e-7.
    outlier_run_ = static_cast<int>(std::clamp(
        std::ceil(std::log(kFalseRestartChance) / std::log(extended_mixture_.outlier_weight)), 3.0,
        10.0));
  }
  filtered_ = extended_mixture_.modes.weight;
  posterior_.resize(m);
}

void SlidingWindowEstimator::reset() {
  outliers_in_a_row_ = 0;
  next_ = 0;
  count_ = 0;
  has_distance_ = false;
  refresh_next_ = 0;
  adds_since_resum_ = 0;
  sums_ = {};
  detector_.reset();
}

// The residual e = y − Hθ̂ − d̂ standardized within its most probable mode (the change
// detector's z, core/change_detector.hpp), from the cached log-priors and precisions of its bin.
double SlidingWindowEstimator::standardized(double residual, int bin,
                                            const Eigen::VectorXd& mean) const {
  const auto b = static_cast<std::size_t>(bin);
  Eigen::Index best = 0;
  double best_log = -INFINITY;
  for (Eigen::Index i = 0; i < mean.size(); ++i) {
    const double r = residual - mean[i];
    const double log_density = log_prior_[b][i] - 0.5 * r * r * precision_[b][i];
    if (log_density > best_log) {
      best_log = log_density;
      best = i;
    }
  }
  return (residual - mean[best]) * inverse_std_[b][best];
}

// P(outlier | e) = ε u / (ε u + (1 − ε) Σ_i π_{b,i} N(e; μ_i, σ²_{b,i})).
double SlidingWindowEstimator::outlier_probability(double residual, int bin,
                                                   const Eigen::VectorXd& mean) const {
  const auto b = static_cast<std::size_t>(bin);
  double largest = log_outlier_;
  double inlier = -INFINITY;
  for (Eigen::Index i = 0; i < mean.size(); ++i) {
    const double r = residual - mean[i];
    const double log_joint =
        log_weight_[b][i] + log_density_shift_[b][i] - 0.5 * r * r * precision_[b][i];
    inlier = std::max(inlier, log_joint);
  }
  largest = std::max(largest, inlier);
  double total = std::exp(log_outlier_ - largest);
  const double outlier = total;
  for (Eigen::Index i = 0; i < mean.size(); ++i) {
    const double r = residual - mean[i];
    total += std::exp(log_weight_[b][i] + log_density_shift_[b][i] -
                      0.5 * r * r * precision_[b][i] - largest);
  }
  return outlier / total;
}

// Whether the change detector sees a change at this range. Under the outlier component a range
// the component takes (P(outlier) > 0.5 at the current d̂) does not enter the CUSUM; a run of
// outlier_run_ of them is a change (a new scene is, at first, a run of "outliers").
bool SlidingWindowEstimator::detect_change(double corrected_range, int bin,
                                           const Eigen::VectorXd& mean) {
  const double residual = corrected_range - distance_;
  if (outlier_run_ > 0 && outlier_probability(residual, bin, mean) > 0.5) {
    if (++outliers_in_a_row_ < outlier_run_) return false;
    detector_.reset();
    return true;
  }
  outliers_in_a_row_ = 0;
  return detector_.update_standardized(standardized(residual, bin, mean));
}

void SlidingWindowEstimator::push(double corrected_range, int bin) {
  ring_[next_] = corrected_range;
  ring_bin_[next_] = bin;
  if (shifted_) ring_shift_.row(next_) = new_shift_.transpose();
  next_ = (next_ + 1) % options_.window;
  count_ = std::min(count_ + 1, options_.window);
}

WindowEstimate SlidingWindowEstimator::add(double corrected_range, int bin,
                                           const Eigen::Ref<const Eigen::VectorXd>& mode_shift) {
  require_finite(corrected_range, "bias-corrected range");
  if (bin < 0 || bin >= extended_mixture_.states()) {
    throw InvalidInput("sliding window: noise state " + std::to_string(bin) +
                       " outside the mixture's " + std::to_string(extended_mixture_.states()) +
                       " states");
  }
  const Eigen::Index m = extended_mixture_.modes.modes();
  if (shifted_) {
    if (mode_shift.size() != m) {
      throw InvalidInput("sliding window: a range needs one offset shift per mode (" +
                         std::to_string(m) + ")");
    }
    require_finite(mode_shift, "mode offset shift");
    new_shift_ = mode_shift;
  } else if (mode_shift.size() > 0 && !mode_shift.isZero()) {
    throw InvalidInput("sliding window: mode offset shifts given to a window made without them");
  }
  WindowEstimate out;
  const Eigen::VectorXd mean =
      shifted_ ? Eigen::VectorXd(extended_mixture_.modes.mean + new_shift_)
               : extended_mixture_.modes.mean;
  if (has_distance_ && count_ >= options_.min_samples &&
      detect_change(corrected_range, bin, mean)) {
    reset();
    out.change_detected = true;
  }
  if (options_.method == WindowEm::Exact) {
    push(corrected_range, bin);
    fit_exact(out);
  } else {
    fit_incremental(corrected_range, bin, out);  // pushes: it needs the slot the range leaves
  }
  has_distance_ = true;
  out.distance = distance_;
  out.samples = count_;
  out.restarting = count_ < options_.min_samples;
  return out;
}

void SlidingWindowEstimator::fit_exact(WindowEstimate& out) {
  // The window oldest first: the ring from next_ when full, from 0 otherwise.
  const Eigen::Index first = count_ == options_.window ? next_ : 0;
  for (Eigen::Index i = 0; i < count_; ++i) {
    ordered_[i] = ring_[(first + i) % options_.window];
    ordered_bin_[i] = ring_bin_[(first + i) % options_.window];
    if (shifted_) ordered_shift_.row(i) = ring_shift_.row((first + i) % options_.window);
  }
  const std::optional<double> warm =
      has_distance_ ? std::optional<double>(distance_) : std::nullopt;
  const EmTestResult fit =
      extended_ ? test_extended_em(ordered_.head(count_), zeros_.head(count_),
                                   ordered_bin_.head(count_),
                                   shifted_ ? Eigen::MatrixXd(ordered_shift_.topRows(count_))
                                            : Eigen::MatrixXd(0, 0),
                                   extended_mixture_, options_.em, warm)
                : test_em(ordered_.head(count_), zeros_.head(count_), extended_mixture_.modes,
                          options_.em, warm);
  distance_ = fit.distance;
  out.posterior = fit.responsibilities.row(count_ - 1).transpose();
  // The modes' responsibilities leave the outlier's out.
  if (extended_) out.outlier = std::max(0.0, 1.0 - out.posterior.sum());
  out.posterior.maxCoeff(&out.most_probable_mode);
  out.distance_std = fit.distance_std;
}

// Eq. 22 for one range x at d, and its terms of the exact M-step's sums (core/em_test.hpp) and
// of Louis' observed information: Σ_i r_i/σ_i² − Var_r[(x − d − μ_i)/σ_i²].
SlidingWindowEstimator::Terms SlidingWindowEstimator::terms_at(double corrected_range,
                                                               double distance) {
  const Eigen::Index m = extended_mixture_.modes.modes();
  double largest = -INFINITY;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double r = corrected_range - distance - extended_mixture_.modes.mean[i];
    posterior_[i] = log_prior_[0][i] - 0.5 * r * r * precision_[0][i];
    largest = std::max(largest, posterior_[i]);
  }
  // exp(0) = 1 for the largest: M − 1 exponentials per range.
  double total = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    posterior_[i] = posterior_[i] == largest ? 1.0 : std::exp(posterior_[i] - largest);
    total += posterior_[i];
  }
  posterior_ /= total;
  Terms t;
  double score_mean = 0.0;
  double score_square = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double score =
        (corrected_range - distance - extended_mixture_.modes.mean[i]) * precision_[0][i];
    t.numerator += posterior_[i] *
                   (corrected_range - reference_ - extended_mixture_.modes.mean[i]) *
                   precision_[0][i];
    t.denominator += posterior_[i] * precision_[0][i];
    score_mean += posterior_[i] * score;
    score_square += posterior_[i] * score * score;
  }
  t.information = t.denominator - (score_square - score_mean * score_mean);
  return t;
}

// The extended E-step of one range (core/extended_mixture.hpp): its bin's weights (under a chain
// the slot's stored forward prior) and variances, and the outlier component, which takes
// responsibility but has no score in d and so adds nothing to the sums.
SlidingWindowEstimator::Terms SlidingWindowEstimator::extended_terms_at(double corrected_range,
                                                                        double distance,
                                                                        std::size_t slot) {
  const Eigen::Index m = extended_mixture_.modes.modes();
  const auto b = static_cast<std::size_t>(ring_bin_[static_cast<Eigen::Index>(slot)]);
  const Eigen::VectorXd mean =
      shifted_ ? Eigen::VectorXd(extended_mixture_.modes.mean +
                                 ring_shift_.row(static_cast<Eigen::Index>(slot)).transpose())
               : extended_mixture_.modes.mean;
  const Eigen::VectorXd& precision = precision_[b];
  double largest = log_outlier_;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double r = corrected_range - distance - mean[i];
    const double log_prior =
        chain_ ? std::log(slot_prior_(static_cast<Eigen::Index>(slot), i)) : log_weight_[b][i];
    posterior_[i] = log_prior + log_density_shift_[b][i] - 0.5 * r * r * precision[i];
    largest = std::max(largest, posterior_[i]);
  }
  double total = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    posterior_[i] = std::exp(posterior_[i] - largest);
    total += posterior_[i];
  }
  outlier_ = std::exp(log_outlier_ - largest);  // 0 without the component
  total += outlier_;
  posterior_ /= total;
  outlier_ /= total;
  Terms t;
  double score_mean = 0.0;
  double score_square = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double score = (corrected_range - distance - mean[i]) * precision[i];
    t.numerator += posterior_[i] * (corrected_range - reference_ - mean[i]) * precision[i];
    t.denominator += posterior_[i] * precision[i];
    score_mean += posterior_[i] * score;
    score_square += posterior_[i] * score * score;
  }
  t.information = t.denominator - (score_square - score_mean * score_mean);
  return t;
}

void SlidingWindowEstimator::resum() {
  sums_ = {};
  for (Eigen::Index i = 0; i < count_; ++i) {
    const Terms& t = terms_[static_cast<std::size_t>(i)];
    sums_.numerator += t.numerator;
    sums_.denominator += t.denominator;
    sums_.information += t.information;
  }
  adds_since_resum_ = 0;
}

void SlidingWindowEstimator::fit_incremental(double corrected_range, int bin, WindowEstimate& out) {
  const auto add_terms = [this](const Terms& t, double sign) {
    sums_.numerator += sign * t.numerator;
    sums_.denominator += sign * t.denominator;
    sums_.information += sign * t.information;
  };
  const auto m_step = [this] {
    // Under the outlier component a window of outliers only has no information: d̂ stays.
    if (!extended_ || sums_.denominator > 0.0) {
      distance_ = reference_ + sums_.numerator / sums_.denominator;
    }
  };
  const auto e_step = [this](double x, std::size_t s) {
    return extended_ ? extended_terms_at(x, distance_, s) : terms_at(x, distance_);
  };
  if (count_ == 0) {
    // A (re)start: the sums are relative to the first range; d̂ starts as em_test's does.
    reference_ = corrected_range;
    distance_ = corrected_range - extended_mixture_.modes.mean_offset();
    sums_ = {};
    adds_since_resum_ = 0;
    refresh_next_ = 0;
    filtered_ = extended_mixture_.modes.weight;  // a chain starts from its initial law
  }
  const std::size_t slot = static_cast<std::size_t>(next_);
  if (count_ == options_.window) add_terms(terms_[slot], -1.0);  // the range leaving
  if (chain_) {
    // The forward prediction P(mode_k | the ranges before it) = α_{k−1}ᵀA, kept for refreshes.
    slot_prior_.row(static_cast<Eigen::Index>(slot)) =
        count_ == 0 ? filtered_.transpose()
                    : (filtered_.transpose() * extended_mixture_.transition).eval();
  }
  push(corrected_range, bin);
  terms_[slot] = e_step(corrected_range, slot);
  add_terms(terms_[slot], 1.0);
  m_step();
  // Redo the E-step of the oldest-refreshed ranges at the new d̂ (the newest was just done).
  const Eigen::Index others = count_ - 1;
  for (int r = 0; r < options_.refreshes && r < others; ++r) {
    refresh_next_ %= others;
    // Age 0 is the oldest range in the window.
    const Eigen::Index oldest = count_ == options_.window ? next_ : 0;
    const auto s = static_cast<std::size_t>((oldest + refresh_next_) % options_.window);
    add_terms(terms_[s], -1.0);
    terms_[s] = e_step(ring_[static_cast<Eigen::Index>(s)], s);
    add_terms(terms_[s], 1.0);
    ++refresh_next_;
  }
  if (++adds_since_resum_ >= options_.window) resum();
  m_step();
  // This range's posterior at the final d̂.
  e_step(corrected_range, slot);
  out.posterior = posterior_;
  out.posterior.maxCoeff(&out.most_probable_mode);
  if (extended_) {
    out.outlier = outlier_;
    if (chain_) filtered_ = posterior_;  // α_k: the chain has no outlier component
  }
  const double information = sums_.information > 0.0 ? sums_.information : sums_.denominator;
  out.distance_std = 1.0 / std::sqrt(information);
}

}  // namespace tofcomp::core
