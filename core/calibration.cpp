#include "core/calibration.hpp"

namespace tofcomp::core {

ExtendedMixture compensation_noise(const Calibration& calibration) {
  return calibration.extension ? calibration.extension->noise
                               : without_extensions(calibration.model.noise);
}

}  // namespace tofcomp::core
