#include "core/squarem.hpp"

#include <algorithm>
#include <cmath>

namespace tofcomp::core {

double SquaremSteps::step_length(const Eigen::Ref<const Eigen::VectorXd>& r,
                                 const Eigen::Ref<const Eigen::VectorXd>& v) {
  const double r_norm = r.norm();
  const double v_norm = v.norm();
  if (!(v_norm > 0.0) || !std::isfinite(r_norm) || !std::isfinite(v_norm)) return 1.0;
  return std::clamp(r_norm / v_norm, 1.0, max_step_);
}

Eigen::VectorXd SquaremSteps::extrapolate(const Eigen::Ref<const Eigen::VectorXd>& x0,
                                          const Eigen::Ref<const Eigen::VectorXd>& r,
                                          const Eigen::Ref<const Eigen::VectorXd>& v,
                                          double alpha) {
  return x0 + (2.0 * alpha) * r + (alpha * alpha) * v;
}

void SquaremSteps::accepted(double alpha) {
  if (alpha >= max_step_) max_step_ *= kStepGrowth;
}

void SquaremSteps::refused(double alpha) {
  if (alpha >= max_step_) max_step_ = std::max(kInitialMaxStep, max_step_ / kStepGrowth);
}

}  // namespace tofcomp::core
