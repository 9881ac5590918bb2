// SQUAREM (Varadhan and Roland, "Simple and globally convergent methods for accelerating the
// convergence of any EM algorithm", Scand. J. Statist. 35, 2008): from a point x0 and two EM
// steps x1 = F(x0), x2 = F(x1), with r = x1 − x0 and v = x2 − 2 x1 + x0, the scheme S3 takes the
// step length α = ‖r‖ / ‖v‖ and the point
//   x' = x0 + 2α r + α² v,
// which is x2 (the plain EM point) at α = 1. α is kept in [1, α_max]; α_max starts at 1 and
// grows by kStepGrowth each time α reaches it, and shrinks by the same factor when a step that
// took the bound is refused (the R package's defaults). The caller checks x' (its
// log-likelihood must not be lower than the last EM point's and it must be valid) and falls back
// to x2 when it is not: the monotone safeguard.
//
// The points are vectors in a parametrization where every x' is a valid model: log variances,
// log-ratio weights, logit probabilities; θ and μ as they are. Shared by core/em_train.cpp and
// core/extended_em.cpp.
#pragma once

#include <Eigen/Core>

namespace tofcomp::core {

// How an EM training iterates: the plain EM map, or SQUAREM on it (the default).
enum class EmAcceleration { None, Squarem };

class SquaremSteps {
 public:
  static constexpr double kInitialMaxStep = 1.0;
  static constexpr double kStepGrowth = 4.0;

  // The step length of S3 for r and v, in [1, the current bound]; 1 when v vanishes (the map is
  // at its fixed point) or the lengths are not finite.
  double step_length(const Eigen::Ref<const Eigen::VectorXd>& r,
                     const Eigen::Ref<const Eigen::VectorXd>& v);
  // x0 + 2α r + α² v.
  static Eigen::VectorXd extrapolate(const Eigen::Ref<const Eigen::VectorXd>& x0,
                                     const Eigen::Ref<const Eigen::VectorXd>& r,
                                     const Eigen::Ref<const Eigen::VectorXd>& v, double alpha);
  // The outcome of the step last taken: the bound grows when the step reached it and was kept,
  // shrinks when it reached it and was refused.
  void accepted(double alpha);
  void refused(double alpha);
  double max_step() const { return max_step_; }

 private:
  double max_step_ = kInitialMaxStep;
};

}  // namespace tofcomp::core
