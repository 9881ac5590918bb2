// What is still (the field calibration's reference, issue 56): one beam's ranges, in time order,
// split into episodes in which the beam sees one fixed surface, and the rest set apart (a person
// or a forklift passing in front, gross errors, a surface seen too briefly to be of use).
//
// A range is still when it lies within `gate_mm` of the surface's level, the running median of
// the last `level_ranges` still ranges: the level follows the slow thermal bias, and the gate
// covers the lasing modes' spread around it. A range outside the gate is set apart unless the
// ranges outside it settle on a level of their own: when the last of them have stayed within
// the gate of their own median for `settle_s` (and at least `level_ranges` of them), the beam
// sees a new surface (a pallet put down, a door shut) and a new episode starts with them.
// Episodes shorter than `min_episode_s` are set apart too: what a still surface teaches the
// calibration is the bias's change over the temperatures it is seen through, and the scanner's
// case changes temperature on the scale of its thermal time constant (R2·C2: 0.40 K/W × 5,800 J/K,
// about 40 minutes, in the first foreign set's network), so a surface seen for a few minutes
// teaches nothing its own distance does not absorb; and a person standing or a forklift parked
// for minutes is not a wall.
// O(level_ranges) per range; no allocation beyond the two buffers.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace tofcomp::core {

inline constexpr int kSetApart = -1;

struct StillEpisodeOptions {
  double gate_mm = 0.0;        // required: the largest distance of a still range from the level
  int level_ranges = 31;       // the running median's length (odd)
  double settle_s = 5.0;       // a new surface is one held this long
  double min_episode_s = 600.0;  // shorter episodes are set apart
};

struct StillEpisode {
  long first = 0;  // index of its first still range
  long last = 0;   // and of its last
  long ranges = 0;  // still ranges in it
};

struct StillSegmentation {
  std::vector<int> episode;  // per range: its episode (0-based, in time order) or kSetApart
  std::vector<StillEpisode> episodes;
  long set_apart = 0;
};

// time_s and range_mm: one beam, non-decreasing times. Throws InvalidInput on a non-positive
// gate, an even or too small level_ranges, mismatched lengths, times going back or non-finite
// values.
StillSegmentation find_still_episodes(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                      const Eigen::Ref<const Eigen::VectorXd>& range_mm,
                                      const StillEpisodeOptions& options);

}  // namespace tofcomp::core
