#include "calibration/final_fit.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/gaussian_mixture.hpp"

namespace tofcomp::calibration {

FinalFit train_em_dropping_emptied_modes(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                         const Eigen::Ref<const Eigen::VectorXd>& y,
                                         core::EmTrainOptions options) {
  FinalFit out;
  // Each pass either returns or has one mode fewer, so this ends by the time one mode is left.
  while (true) {
    try {
      out.em = core::train_em(h, y, options);
      return out;
    } catch (const core::EmptiedModeError& e) {
      if (options.modes < 2) throw;
      out.dropped_modes.push_back(
          fmt::format("mode {} of {} emptied: {}", e.mode() + 1, options.modes, e.what()));
      if (options.start) {
        options.start->mixture = core::without_mode(options.start->mixture, e.mode());
      }
      --options.modes;
    }
  }
}

}  // namespace tofcomp::calibration
