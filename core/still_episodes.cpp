// One beam's still episodes: see still_episodes.hpp.
#include "core/still_episodes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <string>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// The running median is of an odd count at least this, so that one outlier among the still
// ranges cannot move the level.
constexpr int kFewestLevelRanges = 3;

void validate(const Eigen::Ref<const Eigen::VectorXd>& time_s,
              const Eigen::Ref<const Eigen::VectorXd>& range_mm, const StillEpisodeOptions& o) {
  require_same_length(time_s.size(), "the times", range_mm.size(), "the ranges");
  require_finite(time_s, "the times");
  require_finite(range_mm, "the ranges");
  if (!(o.gate_mm > 0.0) || !std::isfinite(o.gate_mm)) {
    throw InvalidInput("still episodes: the gate must be a positive number of millimetres");
  }
  if (o.level_ranges < kFewestLevelRanges || o.level_ranges % 2 == 0) {
    throw InvalidInput("still episodes: level_ranges must be odd and at least " +
                       std::to_string(kFewestLevelRanges));
  }
  if (!(o.settle_s >= 0.0) || !(o.min_episode_s >= 0.0)) {
    throw InvalidInput("still episodes: settle_s and min_episode_s must not be negative");
  }
  for (Eigen::Index k = 1; k < time_s.size(); ++k) {
    if (time_s[k] < time_s[k - 1]) {
      throw InvalidInput("still episodes: time goes back at range " + std::to_string(k));
    }
  }
}

// The median of the last `count` values of `values` (all of them when fewer).
double median_of_last(const std::deque<double>& values, std::size_t count,
                      std::vector<double>& scratch) {
  const std::size_t n = std::min(count, values.size());
  scratch.assign(values.end() - static_cast<std::ptrdiff_t>(n), values.end());
  const auto middle = scratch.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(scratch.begin(), middle, scratch.end());
  return *middle;
}

}  // namespace

StillSegmentation find_still_episodes(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                      const Eigen::Ref<const Eigen::VectorXd>& range_mm,
                                      const StillEpisodeOptions& options) {
  validate(time_s, range_mm, options);
  const Eigen::Index n = range_mm.size();
  const auto window = static_cast<std::size_t>(options.level_ranges);
  std::vector<int> raw(static_cast<std::size_t>(n), kSetApart);
  std::deque<double> level_values;  // the current surface's last still ranges
  // The ranges outside the gate that agree with each other so far: a new surface, if they hold.
  std::deque<double> candidate_values;
  std::vector<Eigen::Index> candidates;
  std::vector<double> scratch;
  int current = kSetApart;
  double current_since_s = 0.0;
  // The surface before the current one, while the current one is younger than min_episode_s:
  // a surface that comes back after a brief one (someone standing in the beam) resumes its
  // episode instead of starting another.
  int before = kSetApart;
  double before_since_s = 0.0;
  std::deque<double> before_values;
  int raw_episodes = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double y = range_mm[k];
    if (current != kSetApart &&
        std::abs(y - median_of_last(level_values, window, scratch)) <= options.gate_mm) {
      raw[static_cast<std::size_t>(k)] = current;
      level_values.push_back(y);
      if (level_values.size() > window) level_values.pop_front();
      candidate_values.clear();
      candidates.clear();
      continue;
    }
    // Outside the surface's gate: a passing object, a gross error, or a new surface.
    if (!candidates.empty() &&
        std::abs(y - median_of_last(candidate_values, window, scratch)) > options.gate_mm) {
      candidate_values.clear();
      candidates.clear();
    }
    candidate_values.push_back(y);
    candidates.push_back(k);
    const bool held = time_s[k] - time_s[candidates.front()] >= options.settle_s &&
                      candidates.size() >= window;
    if (!held) continue;
    // A new surface: its ranges within the gate of their median open the episode, or resume
    // the one before a brief surface.
    const double level = median_of_last(candidate_values, window, scratch);
    const bool brief = current != kSetApart && time_s[k] - current_since_s < options.min_episode_s;
    if (brief && before != kSetApart &&
        std::abs(level - median_of_last(before_values, window, scratch)) <= options.gate_mm) {
      current = before;
      current_since_s = before_since_s;
      before = kSetApart;
    } else {
      if (current != kSetApart && !brief) {
        before = current;
        before_since_s = current_since_s;
        before_values = level_values;
      }
      current = raw_episodes++;
      current_since_s = time_s[candidates.front()];
    }
    level_values.clear();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (std::abs(candidate_values[i] - level) > options.gate_mm) continue;
      raw[static_cast<std::size_t>(candidates[i])] = current;
      level_values.push_back(candidate_values[i]);
      if (level_values.size() > window) level_values.pop_front();
    }
    candidate_values.clear();
    candidates.clear();
  }

  // The episodes long enough to use, renumbered in time order.
  std::vector<StillEpisode> spans(static_cast<std::size_t>(raw_episodes));
  std::vector<bool> seen(static_cast<std::size_t>(raw_episodes), false);
  for (Eigen::Index k = 0; k < n; ++k) {
    const int e = raw[static_cast<std::size_t>(k)];
    if (e == kSetApart) continue;
    StillEpisode& span = spans[static_cast<std::size_t>(e)];
    if (!seen[static_cast<std::size_t>(e)]) span.first = static_cast<long>(k);
    seen[static_cast<std::size_t>(e)] = true;
    span.last = static_cast<long>(k);
    ++span.ranges;
  }
  std::vector<int> renumbered(static_cast<std::size_t>(raw_episodes), kSetApart);
  StillSegmentation out;
  for (int e = 0; e < raw_episodes; ++e) {
    const StillEpisode& span = spans[static_cast<std::size_t>(e)];
    if (time_s[span.last] - time_s[span.first] < options.min_episode_s) continue;
    renumbered[static_cast<std::size_t>(e)] = static_cast<int>(out.episodes.size());
    out.episodes.push_back(span);
  }
  out.episode.resize(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < raw.size(); ++k) {
    out.episode[k] = raw[k] == kSetApart ? kSetApart : renumbered[static_cast<std::size_t>(raw[k])];
    if (out.episode[k] == kSetApart) ++out.set_apart;
  }
  return out;
}

}  // namespace tofcomp::core
