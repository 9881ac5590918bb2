#include "core/sliding_window_estimator.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

SlidingWindowEstimator::SlidingWindowEstimator(MixtureParameters mixture,
                                               SlidingWindowOptions options)
    : mixture_(std::move(mixture)), options_(options), detector_(options.change) {
  mixture_.validate();
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
  ordered_.resize(options_.window);
  zeros_ = Eigen::VectorXd::Zero(options_.window);
  terms_.resize(static_cast<std::size_t>(options_.window));
  precision_ = mixture_.variance.cwiseInverse();
  inverse_std_ = precision_.cwiseSqrt();
  log_prior_ = mixture_.weight.array().log() - 0.5 * mixture_.variance.array().log();
  posterior_.resize(mixture_.modes());
}

void SlidingWindowEstimator::reset() {
  next_ = 0;
  count_ = 0;
  has_distance_ = false;
  refresh_next_ = 0;
  adds_since_resum_ = 0;
  sums_ = {};
  detector_.reset();
}

// The residual e = y − Hθ̂ − d̂ standardized within its most probable mode (the change
// detector's z, core/change_detector.hpp), from the cached log-priors and precisions.
double SlidingWindowEstimator::standardized(double residual) const {
  Eigen::Index best = 0;
  double best_log = -INFINITY;
  for (Eigen::Index i = 0; i < mixture_.modes(); ++i) {
    const double r = residual - mixture_.mean[i];
    const double log_density = log_prior_[i] - 0.5 * r * r * precision_[i];
    if (log_density > best_log) {
      best_log = log_density;
      best = i;
    }
  }
  return (residual - mixture_.mean[best]) * inverse_std_[best];
}

void SlidingWindowEstimator::push(double corrected_range) {
  ring_[next_] = corrected_range;
  next_ = (next_ + 1) % options_.window;
  count_ = std::min(count_ + 1, options_.window);
}

WindowEstimate SlidingWindowEstimator::add(double corrected_range) {
  require_finite(corrected_range, "bias-corrected range");
  WindowEstimate out;
  if (has_distance_ && count_ >= options_.min_samples &&
      detector_.update_standardized(standardized(corrected_range - distance_))) {
    reset();
    out.change_detected = true;
  }
  if (options_.method == WindowEm::Exact) {
    push(corrected_range);
    fit_exact(out);
  } else {
    fit_incremental(corrected_range, out);  // pushes: it needs the slot the range leaves
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
  }
  const EmTestResult fit =
      test_em(ordered_.head(count_), zeros_.head(count_), mixture_, options_.em,
              has_distance_ ? std::optional<double>(distance_) : std::nullopt);
  distance_ = fit.distance;
  out.posterior = fit.responsibilities.row(count_ - 1).transpose();
  out.posterior.maxCoeff(&out.most_probable_mode);
  out.distance_std = fit.distance_std;
}

// Eq. 22 for one range x at d, and its terms of the exact M-step's sums (core/em_test.hpp) and
// of Louis' observed information: Σ_i r_i/σ_i² − Var_r[(x − d − μ_i)/σ_i²].
SlidingWindowEstimator::Terms SlidingWindowEstimator::terms_at(double corrected_range,
                                                               double distance) {
  const Eigen::Index m = mixture_.modes();
  double largest = -INFINITY;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double r = corrected_range - distance - mixture_.mean[i];
    posterior_[i] = log_prior_[i] - 0.5 * r * r * precision_[i];
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
    const double score = (corrected_range - distance - mixture_.mean[i]) * precision_[i];
    t.numerator +=
        posterior_[i] * (corrected_range - reference_ - mixture_.mean[i]) * precision_[i];
    t.denominator += posterior_[i] * precision_[i];
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

void SlidingWindowEstimator::fit_incremental(double corrected_range, WindowEstimate& out) {
  const auto add_terms = [this](const Terms& t, double sign) {
    sums_.numerator += sign * t.numerator;
    sums_.denominator += sign * t.denominator;
    sums_.information += sign * t.information;
  };
  const auto m_step = [this] { distance_ = reference_ + sums_.numerator / sums_.denominator; };
  if (count_ == 0) {
    // A (re)start: the sums are relative to the first range; d̂ starts as em_test's does.
    reference_ = corrected_range;
    distance_ = corrected_range - mixture_.mean_offset();
    sums_ = {};
    adds_since_resum_ = 0;
    refresh_next_ = 0;
  }
  const std::size_t slot = static_cast<std::size_t>(next_);
  if (count_ == options_.window) add_terms(terms_[slot], -1.0);  // the range leaving
  push(corrected_range);
  terms_[slot] = terms_at(corrected_range, distance_);
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
    terms_[s] = terms_at(ring_[static_cast<Eigen::Index>(s)], distance_);
    add_terms(terms_[s], 1.0);
    ++refresh_next_;
  }
  if (++adds_since_resum_ >= options_.window) resum();
  m_step();
  // This range's posterior at the final d̂.
  terms_at(corrected_range, distance_);
  out.posterior = posterior_;
  out.posterior.maxCoeff(&out.most_probable_mode);
  const double information = sums_.information > 0.0 ? sums_.information : sums_.denominator;
  out.distance_std = 1.0 / std::sqrt(information);
}

}  // namespace tofcomp::core
