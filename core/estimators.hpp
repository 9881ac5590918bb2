// §8.4: the three window estimators the paper compares (Fig. 16-19), on windows of any length,
// and the moments of their errors.
//   d̂          EM testing (§6, Eq. 21-23) on the window, warm-started from the previous window;
//   ȳ          the window mean of the raw ranges;
//   mean(y − Hθ̂) − Σπ_iμ_i  the window mean corrected by the temperature bias and centred: less
//                 the modes' common offset Σ_i π_i μ_i, which the paper's mean of y − Hθ̂ keeps
//                 (so that it reads worse than the raw mean whenever the offset is larger than
//                 the bias left in ȳ). It is where EM testing starts (core/em_test.hpp): d̂ before
//                 the modes are assigned.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/em_test.hpp"
#include "core/extended_mixture.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::core {

struct WindowEstimates {
  Eigen::Index window = 0;
  std::vector<Eigen::Index> start;  // first sample of each window
  Eigen::VectorXd em_distance;      // d̂
  Eigen::VectorXd em_distance_std;
  Eigen::VectorXd raw_mean;             // ȳ
  // mean of y − Hθ̂ − Σ_i π_i μ_i: centred by the modes' common offset (with an extended mixture,
  // each range's Σ_i π_{s,i} (μ_i + its shift) under its noise state; the outlier component left
  // aside)
  Eigen::VectorXd bias_corrected_mean;
};

// Every window of `window` consecutive samples starting at 0, stride, 2·stride, ... that fits
// in y (stride 1: every window, as the paper's Fig. 16). O(K/stride · window · iterations).
WindowEstimates estimate_windows(const Eigen::Ref<const Eigen::VectorXd>& y,
                                 const Eigen::Ref<const Eigen::VectorXd>& bias,
                                 const MixtureParameters& mixture, Eigen::Index window,
                                 Eigen::Index stride, const EmTestOptions& options = {});

// The same windows with the extended mixture of core/extended_mixture.hpp (EM testing by
// core/extended_em.hpp), each range with its noise state and its mode offset shifts (K × M, or
// empty for none).
WindowEstimates estimate_windows(const Eigen::Ref<const Eigen::VectorXd>& y,
                                 const Eigen::Ref<const Eigen::VectorXd>& bias,
                                 const Eigen::Ref<const Eigen::VectorXi>& state,
                                 const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                                 const ExtendedMixture& noise, Eigen::Index window,
                                 Eigen::Index stride, const EmTestOptions& options = {});

// The moments of Fig. 18-19 for estimates against the true distances.
struct ErrorMoments {
  Eigen::Index count = 0;
  double mean_error = 0.0;
  double error_variance = 0.0;
  double mean_absolute_error = 0.0;
  double absolute_error_variance = 0.0;
  double rmse = 0.0;
};

ErrorMoments error_moments(const Eigen::Ref<const Eigen::VectorXd>& estimates,
                           const Eigen::Ref<const Eigen::VectorXd>& truth);

}  // namespace tofcomp::core
