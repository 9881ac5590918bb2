#include "core/calibration.hpp"

namespace tofcomp::core {

ExtendedMixture compensation_mixture(const Calibration& calibration) {
  return calibration.extension ? calibration.extension->extended_mixture
                               : without_extensions(calibration.model.mixture);
}

}  // namespace tofcomp::core
