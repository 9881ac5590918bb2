// Real-time EM testing (§6) on one beam: a window of the latest W bias-corrected ranges
// y − H θ̂, re-estimated at every new range from a warm start (the previous window's d̂), and
// restarted when the change detector (core/change_detector.hpp) sees the distance move, so a
// passing object is never averaged with the wall behind it.
// Cost per range: O(W·M·iterations), iterations small from the warm start; memory O(W).
#pragma once

#include <Eigen/Core>

#include "core/change_detector.hpp"
#include "core/em_test.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

struct SlidingWindowOptions {
  Eigen::Index window = 200;      // W
  Eigen::Index min_samples = 10;  // fewer than this after a restart: flagged as restarting
  EmTestOptions em{MStep::Exact, 1e-6, 50, false};
  ChangeDetectorOptions change;
};

struct WindowEstimate {
  double distance = 0.0;  // d̂ of the current window
  double distance_std = 0.0;
  Eigen::Index samples = 0;      // in the window
  bool restarting = false;       // fewer than min_samples since the last (re)start
  bool change_detected = false;  // this range started a new window
  int most_probable_mode = 0;    // of this range (0-based)
};

class SlidingWindowEstimator {
 public:
  SlidingWindowEstimator(MixtureParameters mixture, SlidingWindowOptions options = {});

  // Adds one bias-corrected range y − H θ̂ (finite) and returns the window's estimate.
  WindowEstimate add(double corrected_range);
  void reset();
  const SlidingWindowOptions& options() const { return options_; }

 private:
  MixtureParameters mixture_;
  SlidingWindowOptions options_;
  ChangeDetector detector_;
  Eigen::VectorXd ring_;   // capacity W
  Eigen::Index next_ = 0;  // where the next range goes
  Eigen::Index count_ = 0;
  Eigen::VectorXd ordered_;  // scratch: the window oldest first
  Eigen::VectorXd zeros_;    // scratch: the bias of already corrected ranges
  double distance_ = 0.0;
  bool has_distance_ = false;
};

}  // namespace tofcomp::core
