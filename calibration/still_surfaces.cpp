#include "calibration/still_surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "calibration/measured_data.hpp"

namespace tofcomp::calibration {
namespace {

// Whether the values vary: their interquartile range is not zero.
bool varies(std::vector<double> values) {
  const auto quartile = [&](std::size_t at) {
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at),
                     values.end());
    return values[at];
  };
  const std::size_t n = values.size();
  return quartile(3 * n / 4) > quartile(n / 4);
}

}  // namespace

double still_gate_mm(const core::MixtureParameters& modes) {
  return modes.mean.maxCoeff() - modes.mean.minCoeff() +
         kStillGateModeSpreads * std::sqrt(modes.variance.maxCoeff()) + kRangeResolutionMm;
}

core::StillSegmentation still_surfaces(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                       const Eigen::Ref<const Eigen::VectorXd>& range_mm,
                                       const core::MixtureParameters& modes,
                                       core::StillEpisodeOptions options) {
  if (options.gate_mm == 0.0) options.gate_mm = still_gate_mm(modes);
  core::StillSegmentation s = core::find_still_episodes(time_s, range_mm, options);
  std::vector<std::vector<double>> values(s.episodes.size());
  for (std::size_t k = 0; k < s.episode.size(); ++k) {
    if (s.episode[k] != core::kSetApart) {
      values[static_cast<std::size_t>(s.episode[k])].push_back(range_mm[static_cast<Eigen::Index>(k)]);
    }
  }
  std::vector<int> number(s.episodes.size(), core::kSetApart);
  std::vector<core::StillEpisode> kept;
  for (std::size_t e = 0; e < s.episodes.size(); ++e) {
    if (!varies(values[e])) continue;
    number[e] = static_cast<int>(kept.size());
    kept.push_back(s.episodes[e]);
  }
  s.episodes = std::move(kept);
  s.set_apart = 0;
  for (int& e : s.episode) {
    if (e != core::kSetApart) e = number[static_cast<std::size_t>(e)];
    if (e == core::kSetApart) ++s.set_apart;
  }
  return s;
}

}  // namespace tofcomp::calibration
