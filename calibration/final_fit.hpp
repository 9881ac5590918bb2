// Training's final EM fit (§5) on the structure the search chose (§7), which does not refuse the
// data when a mode the search's looser fit kept empties in the fit to convergence.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "core/em_train.hpp"

namespace tofcomp::calibration {

struct FinalFit {
  core::EmTrainResult em;
  // One line per mode the fit emptied and dropped, in order: which mode of how many, its
  // message (the weight and the iteration).
  std::vector<std::string> dropped_modes;
};

// core::train_em(h, y, options); where it empties a mode (core::EmptiedModeError) and more than
// one is left, that mode is dropped, from the start too when there is one, and EM runs again with
// one mode fewer. The data then do not show the modes the search counted, and the fewer modes are
// what they show. Other errors pass through.
FinalFit train_em_dropping_emptied_modes(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                         const Eigen::Ref<const Eigen::VectorXd>& y,
                                         core::EmTrainOptions options);

}  // namespace tofcomp::calibration
