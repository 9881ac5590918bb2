// Still episodes (core/still_episodes.hpp) on one beam drawn with what the field brings: a wall
// seen through two lasing modes and a slow thermal drift, people walking through the beam, one
// standing in it for half a minute, gross errors, and a pallet put down for good half-way. The
// truth of each range is known here, so the detector's confusion is counted, not eyeballed.
#include "core/still_episodes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

enum class Truth { Wall, Pallet, Passing, Standing, Gross };

struct Beam {
  Eigen::VectorXd time_s;
  Eigen::VectorXd range_mm;
  std::vector<Truth> truth;
};

constexpr double kRateHz = 5.0;
constexpr double kHours = 2.0;
constexpr double kPalletAtS = 3600.0;
constexpr double kWallMm = 3000.0;
constexpr double kPalletMm = 2400.0;
// The modes: offsets 0 and 8 mm, spreads 1.5 and 2 mm, weights 0.7 and 0.3; the gate covers
// their spacing and four of the wider spread.
constexpr double kGateMm = 8.0 + 4.0 * 2.0;

Beam draw_beam(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = static_cast<int>(kHours * 3600.0 * kRateHz);
  Beam b;
  b.time_s.resize(n);
  b.range_mm.resize(n);
  b.truth.resize(static_cast<std::size_t>(n));
  double passing_until = -1.0;
  double next_passing = 200.0;
  for (int k = 0; k < n; ++k) {
    const double t = k / kRateHz;
    b.time_s[k] = t;
    const double drift = 4.0 * std::sin(2.0 * M_PI * t / 7200.0);  // the thermal bias, slow
    const bool upper = unit(rng) < 0.3;
    const double mode = upper ? 8.0 + 2.0 * normal(rng) : 1.5 * normal(rng);
    const double surface = t < kPalletAtS ? kWallMm : kPalletMm;
    double y = std::round(surface + drift + mode);
    Truth truth = t < kPalletAtS ? Truth::Wall : Truth::Pallet;
    if (t >= next_passing) {  // someone walks through: 5-40 s
      passing_until = t + 5.0 + 35.0 * unit(rng);
      next_passing = t + 300.0 + 600.0 * unit(rng);
    }
    if (t < passing_until) {
      y = std::round(1200.0 + 400.0 * std::sin(t) + 30.0 * normal(rng));
      truth = Truth::Passing;
    }
    if (t >= 5000.0 && t < 5030.0) {  // someone stands in the beam for 30 s
      y = std::round(1800.0 + 3.0 * normal(rng));
      truth = Truth::Standing;
    }
    if (unit(rng) < 0.002) {
      y = unit(rng) < 0.5 ? 8183.0 : 0.0;
      truth = Truth::Gross;
    }
    b.range_mm[k] = y;
    b.truth[static_cast<std::size_t>(k)] = truth;
  }
  return b;
}

TEST(StillEpisodes, TheWallAndThePalletAreStillWhatPassesIsSetApart) {
  const Beam b = draw_beam(7);
  StillEpisodeOptions options;
  options.gate_mm = kGateMm;
  const StillSegmentation s = find_still_episodes(b.time_s, b.range_mm, options);
  long still = 0, still_set_apart = 0, moving = 0, moving_kept = 0;
  for (std::size_t k = 0; k < b.truth.size(); ++k) {
    const bool kept = s.episode[k] != kSetApart;
    if (b.truth[k] == Truth::Wall || b.truth[k] == Truth::Pallet) {
      ++still;
      still_set_apart += kept ? 0 : 1;
    } else {
      ++moving;
      moving_kept += kept ? 1 : 0;
    }
  }
  // The bars: at most 2 % of still ranges set apart, at least 99 % of the rest.
  EXPECT_LE(static_cast<double>(still_set_apart), 0.02 * static_cast<double>(still))
      << still_set_apart << " of " << still;
  EXPECT_LE(static_cast<double>(moving_kept), 0.01 * static_cast<double>(moving))
      << moving_kept << " of " << moving;
  // Two surfaces: the wall before the pallet, the pallet after it, each one episode (the pallet
  // seen again after someone stood in front of it resumes its episode).
  ASSERT_EQ(s.episodes.size(), 2u);
  EXPECT_LT(b.time_s[s.episodes[0].last], kPalletAtS);
  EXPECT_GE(b.time_s[s.episodes[1].first], kPalletAtS);
  EXPECT_LT(b.time_s[s.episodes[1].first], kPalletAtS + 60.0);
  for (std::size_t k = 0; k < b.truth.size(); ++k) {
    if (s.episode[k] == 0) {
      EXPECT_NE(b.truth[k], Truth::Pallet) << k;
    } else if (s.episode[k] == 1) {
      EXPECT_NE(b.truth[k], Truth::Wall) << k;
    }
  }
  EXPECT_EQ(s.set_apart, std::count(s.episode.begin(), s.episode.end(), kSetApart));
}

TEST(StillEpisodes, ABeamThatNeverSettlesHasNoEpisode) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = 3000;
  Eigen::VectorXd t(n), y(n);
  for (int k = 0; k < n; ++k) {
    t[k] = k / kRateHz;
    y[k] = 2000.0 + 500.0 * normal(rng);  // open space: clutter at every range
  }
  StillEpisodeOptions options;
  options.gate_mm = kGateMm;
  const StillSegmentation s = find_still_episodes(t, y, options);
  EXPECT_TRUE(s.episodes.empty());
  EXPECT_EQ(s.set_apart, n);
}

TEST(StillEpisodes, BadArgumentsAreNamed) {
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(10, 0.0, 9.0);
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(10, 1000.0);
  StillEpisodeOptions options;
  EXPECT_THROW(find_still_episodes(t, y, options), InvalidInput);  // no gate
  options.gate_mm = 10.0;
  options.level_ranges = 30;
  EXPECT_THROW(find_still_episodes(t, y, options), InvalidInput);
  options.level_ranges = 31;
  Eigen::VectorXd back = t;
  back[4] = 1.0;
  try {
    find_still_episodes(back, y, options);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "still episodes: time goes back at range 4");
  }
}

}  // namespace
}  // namespace tofcomp::core
