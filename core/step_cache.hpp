// The discretization of Eq. 3 over a step (Eq. 5-6, a matrix exponential), kept for the last few
// distinct steps. A record that merges two regular clocks (ranges every 0.25 s, case readings
// every second, so steps of 0.25 s and 0 s in turn) alternates between a few steps; keeping only
// the last one recomputed the exponentials at every switch, which was a quarter of training's time
// on a day of data. The key is the step itself, compared exactly, so the cached model is the one
// that would be computed: no answer changes.
#pragma once

#include <array>
#include <cstddef>
#include <utility>

namespace tofcomp::core {

// Distinct steps kept: a merged grid of two or three clocks has that many steps and a few more
// from its rounding.
inline constexpr std::size_t kStepCacheCapacity = 8;

template <typename Model>
class StepCache {
 public:
  // The model for step_s: the cached one, or make(step_s) cached in the oldest slot.
  template <typename Make>
  const Model& at(double step_s, Make&& make) {
    for (std::size_t i = 0; i < size_; ++i) {
      if (step_[i] == step_s) return model_[i];
    }
    const std::size_t slot = next_;
    next_ = (next_ + 1) % kStepCacheCapacity;
    if (size_ < kStepCacheCapacity) ++size_;
    model_[slot] = std::forward<Make>(make)(step_s);
    step_[slot] = step_s;
    return model_[slot];
  }

 private:
  std::array<double, kStepCacheCapacity> step_{};
  std::array<Model, kStepCacheCapacity> model_{};
  std::size_t size_ = 0;
  std::size_t next_ = 0;
};

}  // namespace tofcomp::core
