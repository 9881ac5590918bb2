// A calibration with round numbers for the real-time tests: the thermal network of
// tests/support/thermal_examples.hpp (R1 = 2 K/W, P = 3 W: the junction sits P·R1 = 6 K above
// the case at rest with the laser on), a bias H(t)θ = 0.5 mm/°C · t (raw polynomial of order 1,
// no scaling), and the paper's two lasing modes 4.5 mm apart.
#pragma once

#include <memory>

#include "core/calibration.hpp"
#include "tests/support/synthetic_measurements.hpp"
#include "tests/support/thermal_examples.hpp"

namespace tofcomp::testing {

inline core::Calibration round_calibration() {
  core::Calibration c;
  c.thermal = round_thermal_parameters();
  c.ambient_c = 22.0;
  c.model.basis = core::Basis(
      {core::BasisTerm{core::BasisKind::Polynomial, 1, core::PolynomialForm::RawPower, 0.0}},
      core::TemperatureScaling{0.0, 1.0});
  c.model.theta = Eigen::VectorXd::Constant(1, 0.5);
  c.model.mixture = mixture({-2.0, 2.5}, {0.9, 1.1}, {0.55, 0.45});
  return c;
}

}  // namespace tofcomp::testing
