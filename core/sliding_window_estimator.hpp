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
//
// Under the extended mixture of core/extended_mixture.hpp (a calibration's model extension,
// core/model_extension.hpp) each range carries its temperature bin b(k) (the junction's bin at
// its scan) and both methods test d as core/extended_em.hpp does:
// - Exact: test_extended_em on the window, the bins with it.
// - Incremental: a range's terms use its bin's weights and variances; the outlier component
//   takes responsibility but no weight, w_ki = r_ki / σ²_{b(k),i}. Under a Markov chain over
//   the modes a new range's prior is the forward (filtered) prediction α_{k−1}ᵀA from the
//   filtered posterior of the range before it (the window's first range: the chain's initial
//   law π), stored per slot so that a refresh reuses it. Its responsibilities are the filtered
//   P(mode_k | ranges up to k), not the batch smoother's P(mode_k | whole window): an
//   approximation (tests/core/sliding_window_test.cpp bounds its effect on d̂).
// With an outlier component a range it takes (P(outlier) > 0.5 at the current d̂) does not
// enter the change detector's CUSUM; a run of n of them restarts the window, n the smallest
// with ε^n < 1e-7 (from 3 to 10): a new scene first looks like a run of outliers. Without an
// extension every result is the plain mixture's, bit for bit.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/change_detector.hpp"
#include "core/em_test.hpp"
#include "core/extended_mixture.hpp"
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
  bool operator==(const SlidingWindowOptions&) const = default;
};

struct WindowEstimate {
  double distance = 0.0;  // d̂ of the current window
  double distance_std = 0.0;
  Eigen::VectorXd posterior;     // P(mode i | this range, d̂): the responsibilities of Eq. 22
  Eigen::Index samples = 0;      // in the window
  bool restarting = false;       // fewer than min_samples since the last (re)start
  bool change_detected = false;  // this range started a new window
  int most_probable_mode = 0;    // of this range (0-based)
  double outlier = 0.0;          // P(this range is an outlier | d̂): 0 without the component
};

class SlidingWindowEstimator {
 public:
  // The paper's mixture: the same as without_extensions(mixture).
  SlidingWindowEstimator(MixtureParameters mixture, SlidingWindowOptions options = {});
  // The extended mixture. Throws InvalidInput when it is invalid.
  // With mode_shifts, every range comes with its shift of each mode's offset (a calibration's
  // mode-offset terms, core/model_extension.hpp).
  SlidingWindowEstimator(ExtendedMixture extended_mixture, SlidingWindowOptions options = {},
                         bool mode_shifts = false);

  // Adds one bias-corrected range y − H θ̂ (finite) of noise state `bin` (0..S−1 of the
  // extended mixture; 0 without bins) and, for a window made with mode shifts, its shift of each
  // mode's offset; returns the window's estimate. Throws InvalidInput on a non-finite range, a
  // state out of range or shifts that do not fit the window.
  WindowEstimate add(double corrected_range, int bin = 0,
                     const Eigen::Ref<const Eigen::VectorXd>& mode_shift = Eigen::VectorXd());
  void reset();
  const SlidingWindowOptions& options() const { return options_; }
  const MixtureParameters& mixture() const { return extended_mixture_.modes; }
  const ExtendedMixture& extended_mixture() const { return extended_mixture_; }

 private:
  // One range's terms of the incremental sums, evaluated at the d̂ of its last E-step.
  struct Terms {
    double numerator = 0.0;    // Σ_i r_i (x − ref − μ_i)/σ_i²
    double denominator = 0.0;  // Σ_i r_i / σ_i²: complete-data information
    double information = 0.0;  // observed information (Louis): denominator − Var_r(score)
  };
  void push(double corrected_range, int bin);
  void fit_exact(WindowEstimate& out);
  void fit_incremental(double corrected_range, int bin, WindowEstimate& out);
  // E-step of one range at d: fills posterior_ and returns its terms.
  Terms terms_at(double corrected_range, double distance);
  // The same under the extended mixture for the range in ring slot `slot` (its bin and, under a
  // chain, its stored prior); also fills outlier_.
  Terms extended_terms_at(double corrected_range, double distance, std::size_t slot);
  void resum();
  // With each mode's offset (shifted, for a range with mode shifts).
  double standardized(double residual, int bin, const Eigen::VectorXd& mean) const;
  double outlier_probability(double residual, int bin, const Eigen::VectorXd& mean) const;
  bool detect_change(double corrected_range, int bin, const Eigen::VectorXd& mean);

  ExtendedMixture extended_mixture_;
  bool extended_ = false;  // extended_mixture_.has_extension()
  bool chain_ = false;     // a Markov chain over the modes
  bool shifted_ = false;   // ranges come with mode offset shifts
  Eigen::MatrixXd ring_shift_;     // W × M: each range's shifts (shifted_ only)
  Eigen::MatrixXd ordered_shift_;  // scratch
  Eigen::VectorXd new_shift_;      // the shifts of the range being added
  SlidingWindowOptions options_;
  ChangeDetector detector_;
  Eigen::VectorXd ring_;      // capacity W
  Eigen::VectorXi ring_bin_;  // the bin of each range in ring_
  Eigen::Index next_ = 0;     // where the next range goes
  Eigen::Index count_ = 0;
  Eigen::VectorXd ordered_;  // scratch: the window oldest first
  Eigen::VectorXi ordered_bin_;
  Eigen::VectorXd zeros_;  // scratch: the bias of already corrected ranges
  double distance_ = 0.0;
  bool has_distance_ = false;
  // Incremental only.
  std::vector<Terms> terms_;       // per ring slot
  Eigen::Index refresh_next_ = 0;  // the oldest-refreshed range, as an age from the oldest
  Eigen::Index adds_since_resum_ = 0;
  double reference_ = 0.0;  // x of the window's first range
  Terms sums_;
  // Per temperature bin b (one without bins):
  std::vector<Eigen::VectorXd> log_prior_;    // log π_{b,i} − ½ log σ_{b,i}²
  std::vector<Eigen::VectorXd> precision_;    // 1/σ_{b,i}²
  std::vector<Eigen::VectorXd> inverse_std_;  // 1/σ_{b,i}
  // Extended, incremental only:
  std::vector<Eigen::VectorXd> log_weight_;         // log π_{b,i}
  std::vector<Eigen::VectorXd> log_density_shift_;  // log(1 − ε) − ½ log(2π σ_{b,i}²)
  double log_outlier_ = 0.0;                        // log(ε u); −∞ without the component
  Eigen::MatrixXd slot_prior_;  // W × M: under a chain, each slot's prior α_{k−1}ᵀA
  Eigen::VectorXd filtered_;    // under a chain: the newest range's filtered posterior
  double outlier_ = 0.0;        // scratch: the outlier responsibility of the last E-step
  int outlier_run_ = 0;         // outliers in a row that make a change; 0: no component
  int outliers_in_a_row_ = 0;
  Eigen::VectorXd posterior_;  // scratch
};

}  // namespace tofcomp::core
