// Thermal parameters shared by the thermal tests.
#pragma once

#include "core/thermal_model.hpp"

namespace tofcomp::testing {

// Round numbers for hand computation, with fast time constants (≈ 6 s and 64 s) so that short
// records exercise the dynamics: R1 = 2, R2 = 4, C1 = 5, C2 = 10, P = 3.
inline core::ThermalParameters round_thermal_parameters() {
  return core::ThermalParameters{2.0, 4.0, 5.0, 10.0, 3.0};
}

}  // namespace tofcomp::testing
