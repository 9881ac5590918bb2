// Real-time EM testing (§6) on one beam: a window of the latest W bias-corrected ranges
// y − H θ̂, re-estimated at every new range from a warm start (the previous window's d̂), and
// restarted when the change detector (core/change_detector.hpp) sees the distance move, so a
// passing object is never averaged with the wall behind it.
//
// Two ways to reach the window's d̂, chosen by SlidingWindowOptions::method:
// - Exact: the batch EM test (core/em_test.hpp) of the whole window at every range, from the
//   warm start. Cost per range O(W·M·iterations); d̂ is the window's maximum-likelihood value.
// - Incremental: Neal and Hinton's incremental EM (1998) on the window's sufficient statistics
//   of the exact M-step (core/em_test.hpp),
//     d̂ = Σ_k Σ_i r_ki (x_k − μ_i)/σ_i² / Σ_k Σ_i r_ki / σ_i²,   x_k = y_k − H_k θ̂,
//   kept as running sums: a new range adds its terms, the range leaving the window takes its
//   terms away, and the E-step (Eq. 22) of `refreshes` of the oldest-refreshed ranges is redone
//   at the current d̂, so every range's responsibilities are renewed each W / refreshes ranges.
//   It has the batch fixed point (a window that stops changing converges to the exact d̂) and
//   costs O(M·(1 + refreshes)) per range, for the daemon's 361 beams at 75 scans/s. Sums are
//   kept relative to the window's first range (no cancellation against a 3 m offset) and
//   re-added from the stored terms every W ranges, so rounding cannot accumulate.
// Memory O(W) either way.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/change_detector.hpp"
#include "core/em_test.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

enum class WindowEm { Exact, Incremental };

struct SlidingWindowOptions {
  Eigen::Index window = 200;      // W
  Eigen::Index min_samples = 10;  // fewer than this after a restart: flagged as restarting
  WindowEm method = WindowEm::Exact;
  EmTestOptions em{MStep::Exact, 1e-6, 50, false};  // Exact only
  int refreshes = 4;                                // Incremental only: E-steps redone per range
  ChangeDetectorOptions change;
};

struct WindowEstimate {
  double distance = 0.0;  // d̂ of the current window
  double distance_std = 0.0;
  Eigen::VectorXd posterior;     // P(mode i | this range, d̂): the responsibilities of Eq. 22
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
  const MixtureParameters& mixture() const { return mixture_; }

 private:
  // One range's terms of the incremental sums, evaluated at the d̂ of its last E-step.
  struct Terms {
    double numerator = 0.0;    // Σ_i r_i (x − ref − μ_i)/σ_i²
    double denominator = 0.0;  // Σ_i r_i / σ_i²: complete-data information
    double information = 0.0;  // observed information (Louis): denominator − Var_r(score)
  };
  void push(double corrected_range);
  void fit_exact(WindowEstimate& out);
  void fit_incremental(double corrected_range, WindowEstimate& out);
  // E-step of one range at d: fills posterior_ and returns its terms.
  Terms terms_at(double corrected_range, double distance);
  void resum();
  double standardized(double residual) const;

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
  // Incremental only.
  std::vector<Terms> terms_;       // per ring slot
  Eigen::Index refresh_next_ = 0;  // the oldest-refreshed range, as an age from the oldest
  Eigen::Index adds_since_resum_ = 0;
  double reference_ = 0.0;  // x of the window's first range
  Terms sums_;
  Eigen::VectorXd log_prior_;    // log π_i − ½ log σ_i²
  Eigen::VectorXd precision_;    // 1/σ_i²
  Eigen::VectorXd inverse_std_;  // 1/σ_i
  Eigen::VectorXd posterior_;    // scratch
};

}  // namespace tofcomp::core
