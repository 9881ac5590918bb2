// Bases named on the command line: terms joined by '+', each
//   polynomial:N[:legendre|raw]   (Eq. 9; Legendre by default)
//   fourier:N:F0                  (Eq. 11; F0 in 1/°C)
// e.g. "polynomial:4", "polynomial:2+fourier:3:0.125". Polynomial terms are scaled to the
// given temperatures.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/basis.hpp"

namespace tofcomp::calibration {

// Throws core::InvalidInput naming the malformed term.
core::Basis parse_basis(const std::string& spec,
                        const Eigen::Ref<const Eigen::VectorXd>& temperatures_c);

// "polynomial:1..16" expands to sixteen candidates; other specs stand for themselves.
std::vector<core::Basis> parse_candidates(const std::vector<std::string>& specs,
                                          const Eigen::Ref<const Eigen::VectorXd>& temperatures_c);

}  // namespace tofcomp::calibration
