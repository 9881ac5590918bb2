// The still surfaces of one beam (issue 56), as the field training and `tofcomp replay` take
// them: core/still_episodes.hpp's episodes with a gate from a calibration's lasing modes, less the
// episodes whose ranges never vary (a code the device reports, not a surface seen through its
// lasing modes, whose spread the datasheet puts at 5 mm, 1σ).
#pragma once

#include <Eigen/Core>

#include "core/gaussian_mixture.hpp"
#include "core/still_episodes.hpp"

namespace tofcomp::calibration {

// A still range lies within this many of the widest mode's σ of the surface's level, beyond the
// modes' own spacing (a lasing mode's range falls outside with probability 6e-5).
inline constexpr double kStillGateModeSpreads = 4.0;

// (μ_max − μ_min) + kStillGateModeSpreads × σ_max + the range resolution.
double still_gate_mm(const core::MixtureParameters& modes);

// One beam's still episodes (options.gate_mm 0: still_gate_mm(modes)); the episodes of a code
// are set apart and the others renumbered.
core::StillSegmentation still_surfaces(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                       const Eigen::Ref<const Eigen::VectorXd>& range_mm,
                                       const core::MixtureParameters& modes,
                                       core::StillEpisodeOptions options);

}  // namespace tofcomp::calibration
