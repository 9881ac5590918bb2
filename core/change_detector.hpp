// Detection of a change of the true distance d on one beam (a passing object, a moved target),
// so that the sliding window of §6 never averages two scenes. A two-sided CUSUM test
// (Basseville and Nikiforov, the paper's ref. [16]) on the standardized, mode-compensated
// residual z_k = (y_k − H_kθ̂ − μ_i − d̂) / σ_i of the sample's most probable mode i:
//   g⁺_k = max(0, g⁺_{k−1} + z_k − drift),   g⁻_k = max(0, g⁻_{k−1} − z_k − drift),
// alarm when either exceeds the threshold. With drift ν and threshold h it detects a shift of δ
// standard deviations after about h / (δ − ν) samples; the mean time between false alarms on
// Gaussian residuals grows like exp(2νh) (Siegmund's approximation).
// O(M) per sample, no allocation.
#pragma once

#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

struct ChangeDetectorOptions {
  double drift = 1.0;       // ν, in standard deviations: half the smallest shift to detect
  double threshold = 12.0;  // h
  bool operator==(const ChangeDetectorOptions&) const = default;
};

class ChangeDetector {
 public:
  explicit ChangeDetector(ChangeDetectorOptions options = {});

  // Feeds one residual e = y − H θ̂ − d̂ (the mixture's modes still in it). Returns true on an
  // alarm, after which the statistics restart from zero. Throws InvalidInput on a non-finite e.
  bool update(double residual, const MixtureParameters& mixture);
  // The same, for a caller that has already standardized the residual within its most probable
  // mode: z = (e − μ_i) / σ_i. Throws InvalidInput on a non-finite z.
  bool update_standardized(double z);
  void reset();

  double upper() const { return upper_; }
  double lower() const { return lower_; }

 private:
  ChangeDetectorOptions options_;
  double upper_ = 0.0;
  double lower_ = 0.0;
};

}  // namespace tofcomp::core
