#include "core/sliding_window_estimator.hpp"

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
  ring_.resize(options_.window);
  ordered_.resize(options_.window);
  zeros_ = Eigen::VectorXd::Zero(options_.window);
}

void SlidingWindowEstimator::reset() {
  next_ = 0;
  count_ = 0;
  has_distance_ = false;
  detector_.reset();
}

WindowEstimate SlidingWindowEstimator::add(double corrected_range) {
  require_finite(corrected_range, "bias-corrected range");
  WindowEstimate out;
  if (has_distance_ && count_ >= options_.min_samples &&
      detector_.update(corrected_range - distance_, mixture_)) {
    reset();
    out.change_detected = true;
  }
  ring_[next_] = corrected_range;
  next_ = (next_ + 1) % options_.window;
  count_ = std::min(count_ + 1, options_.window);
  // The window oldest first: the ring from next_ when full, from 0 otherwise.
  const Eigen::Index first = count_ == options_.window ? next_ : 0;
  for (Eigen::Index i = 0; i < count_; ++i) {
    ordered_[i] = ring_[(first + i) % options_.window];
  }
  const EmTestResult fit =
      test_em(ordered_.head(count_), zeros_.head(count_), mixture_, options_.em,
              has_distance_ ? std::optional<double>(distance_) : std::nullopt);
  distance_ = fit.distance;
  has_distance_ = true;
  fit.responsibilities.row(count_ - 1).maxCoeff(&out.most_probable_mode);
  out.distance = fit.distance;
  out.distance_std = fit.distance_std;
  out.samples = count_;
  out.restarting = count_ < options_.min_samples;
  return out;
}

}  // namespace tofcomp::core
