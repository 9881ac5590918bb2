// The residual tests (core/residual_diagnosis.hpp) on records drawn from Eq. 8 with the ranges
// rounded to whole millimetres as the LMS 200 reports them: judged by draws of the model they
// keep their false-alarm rate where the textbook laws do not, they find what a broad mode holds
// as outliers, and they give one result on any number of threads.
#include "core/residual_diagnosis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <random>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/residual_statistics.hpp"

namespace tofcomp::core {
namespace {

constexpr Eigen::Index kDiagnosedRanges = 20000;
constexpr double kCycleS = 4000.0;  // one power cycle: the junction warms up from 25 °C

// Two overlapping lasing modes (2.4 mm apart, σ 1.0 and 1.2 mm).
MixtureParameters overlapping_modes() {
  MixtureParameters m;
  m.mean = Eigen::Vector2d(-1.0, 1.4);
  m.variance = Eigen::Vector2d(1.0, 1.44);
  m.weight = Eigen::Vector2d(0.5, 0.5);
  return m;
}

// The modes as a fit to their values rounded to whole millimetres reports them: each variance
// with the rounding's 1/12 mm² in it.
MixtureParameters as_fitted(MixtureParameters m) {
  m.variance.array() += 1.0 / 12.0;
  return m;
}

// What a record may hold besides Eq. 8.
enum class Extra { None, HotterModeTwo };

// One range a second over five power cycles; the junction rises 6 K after each power-on
// (τ 800 s) and the bias 0.9 mm/K with it, so d + H θ sweeps the rounding's lattice about five
// times a cycle. y = round(d + H θ + w), w from `modes`; with HotterModeTwo the second mode's
// weight rises from 0.3 to 0.7 with the junction, and the bias takes in the mean this moves, as
// training's would. The residual is y − d − H θ, the bias known.
DiagnosisInput rounded_record(std::uint64_t seed, const MixtureParameters& modes, Extra extra) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  DiagnosisInput in;
  in.time_s.resize(kDiagnosedRanges);
  in.junction_c.resize(kDiagnosedRanges);
  in.junction_rate_c_per_s.resize(kDiagnosedRanges);
  in.time_since_power_on_s.resize(kDiagnosedRanges);
  in.residual.resize(kDiagnosedRanges);
  in.predicted_mm.resize(kDiagnosedRanges);
  for (Eigen::Index k = 0; k < kDiagnosedRanges; ++k) {
    const double t = static_cast<double>(k);
    const double on = std::fmod(t, kCycleS);
    in.time_s[k] = t;
    in.time_since_power_on_s[k] = on;
    in.junction_c[k] = 25.0 + 6.0 * (1.0 - std::exp(-on / 800.0));
    in.junction_rate_c_per_s[k] = 6.0 / 800.0 * std::exp(-on / 800.0);
    in.predicted_mm[k] = 3000.0 + 0.9 * (in.junction_c[k] - 25.0);
    const double second = extra == Extra::HotterModeTwo
                              ? 0.3 + 0.4 * (in.junction_c[k] - 25.0) / 6.0
                              : modes.weight[1];
    in.predicted_mm[k] += (second - modes.weight[1]) * (modes.mean[1] - modes.mean[0]);
    const int mode = uniform(rng) < second ? 1 : 0;
    const double w = modes.mean[mode] + std::sqrt(modes.variance[mode]) * normal(rng);
    in.residual[k] = std::round(in.predicted_mm[k] + w) - in.predicted_mm[k];
  }
  return in;
}

DiagnosisOptions rounded(int draws) {
  DiagnosisOptions options;
  options.resolution_mm = 1.0;
  options.null_draws = draws;
  return options;
}

bool any_significant(const Diagnosis& d) {
  return std::any_of(d.findings.begin(), d.findings.end(),
                     [](const Finding& f) { return f.significant; });
}

const Finding& finding(const Diagnosis& d, EffectKind kind) {
  const auto it = std::find_if(d.findings.begin(), d.findings.end(),
                               [&](const Finding& f) { return f.kind == kind; });
  EXPECT_NE(it, d.findings.end()) << effect_name(kind);
  return *it;
}

TEST(ResidualRanks, AreTheSortedOrderWithTiesByPosition) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(-50.0, 50.0);
  Eigen::VectorXd v(5000);
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = uniform(rng);
  v[17] = v[4000] = v[123] = 2.5;  // ties: by position
  std::vector<Eigen::Index> order(static_cast<std::size_t>(v.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return v[a] < v[b]; });
  const Eigen::VectorXd r = ranks(v);
  for (std::size_t i = 0; i < order.size(); ++i) {
    ASSERT_EQ(r[order[i]], static_cast<double>(i)) << "value " << v[order[i]];
  }
  EXPECT_LT(r[17], r[123]);
  EXPECT_LT(r[123], r[4000]);
}

// Twenty records of Eq. 8 alone. The textbook laws flag most of them (the rounding's lattice
// moves with the bias: e's mean and the modes' shares change with the junction temperature);
// judged by the model's draws, at 5 % family-wise, at most 3 of 20 may raise a finding
// (P(X ≥ 4) = 1.6 % for a binomial(20, 0.05)).
TEST(ResidualDiagnosis, RoundedRangesOfTheModelRaiseFindingsAtTheStatedRate) {
  const MixtureParameters modes = overlapping_modes();
  const MixtureParameters fitted = as_fitted(modes);
  int textbook_alarms = 0, alarms = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const DiagnosisInput in = rounded_record(seed, modes, Extra::None);
    textbook_alarms += any_significant(diagnose_residuals(in, fitted, rounded(0)));
    const Diagnosis d = diagnose_residuals(in, fitted, rounded(kResidualNullDraws));
    alarms += any_significant(d);
    for (const Finding& f : d.findings) {
      EXPECT_TRUE(std::isfinite(f.result.p_value)) << effect_name(f.kind);
      EXPECT_TRUE(std::isfinite(f.result.z)) << effect_name(f.kind);
    }
  }
  std::cout << "records raising a finding: textbook laws " << textbook_alarms << "/20, the model's "
            << "draws " << alarms << "/20\n";
  EXPECT_GE(textbook_alarms, 15) << "the records do not show the rounding's effect";
  EXPECT_LE(alarms, 3);
}

// The same records unrounded: the textbook laws hold there, and the draws (unrounded too) agree.
TEST(ResidualDiagnosis, UnroundedRangesOfTheModelRaiseFindingsAtTheStatedRateEitherWay) {
  const MixtureParameters modes = overlapping_modes();
  int textbook_alarms = 0, alarms = 0;
  for (std::uint64_t seed = 101; seed <= 120; ++seed) {
    DiagnosisInput in = rounded_record(seed, modes, Extra::None);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> dither(-0.5, 0.5);
    for (Eigen::Index k = 0; k < in.residual.size(); ++k) in.residual[k] += dither(rng);
    DiagnosisOptions options;
    options.null_draws = 0;
    const MixtureParameters fitted = as_fitted(modes);  // the dither's variance too
    textbook_alarms += any_significant(diagnose_residuals(in, fitted, options));
    options.null_draws = kResidualNullDraws;
    alarms += any_significant(diagnose_residuals(in, fitted, options));
  }
  std::cout << "records raising a finding: textbook laws " << textbook_alarms << "/20, the model's "
            << "draws " << alarms << "/20\n";
  EXPECT_LE(textbook_alarms, 3);
  EXPECT_LE(alarms, 3);
}

// An effect is still found: the second mode's weight rising with the junction temperature (the
// shares' χ² significant; the modes it smears about the bias that took in their mean raise the
// test of one more mode too).
TEST(ResidualDiagnosis, FindsTemperatureDependentWeightsOnRoundedRanges) {
  const MixtureParameters modes = overlapping_modes();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Diagnosis d = diagnose_residuals(rounded_record(seed, modes, Extra::HotterModeTwo),
                                           as_fitted(modes), rounded(kResidualNullDraws));
    const Finding& weights = finding(d, EffectKind::TemperatureDependentWeights);
    EXPECT_TRUE(weights.significant) << "p " << weights.result.p_value;
    EXPECT_GT(weights.result.z, 10.0);
  }
}

// Lasing modes of unequal spread (σ 0.7 and 2.7 mm) put no range beyond 8 σ of its own mode, so
// the outliers' test finds none; 2 % of ranges spread over ±100 mm, which a two-mode fit holds
// in a mode of σ 47 mm (and both lasing modes in one), are found against the lasing mode's
// robust spread.
TEST(ResidualDiagnosis, MeasuresOutliersAgainstEachLasingModesOwnSpread) {
  MixtureParameters unequal;
  unequal.mean = Eigen::Vector2d(-2.6, 3.6);
  unequal.variance = Eigen::Vector2d(2.7 * 2.7, 0.7 * 0.7);
  unequal.weight = Eigen::Vector2d(0.32, 0.68);
  const DiagnosisInput clean = rounded_record(5, unequal, Extra::None);
  const Diagnosis d = diagnose_residuals(clean, unequal, rounded(0));
  const Finding& none = finding(d, EffectKind::Outliers);
  EXPECT_EQ(none.result.statistic, 0.0);
  EXPECT_FALSE(none.significant);
  EXPECT_EQ(d.lasing_modes, (std::vector<int>{0, 1}));
  EXPECT_NEAR(d.mode_scale_mm[0], 2.7, 0.15);
  EXPECT_NEAR(d.mode_scale_mm[1], 0.7, 0.05);

  const MixtureParameters modes = overlapping_modes();
  DiagnosisInput with_outliers = rounded_record(6, modes, Extra::None);
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int outliers = 0;
  for (Eigen::Index k = 0; k < with_outliers.residual.size(); ++k) {
    if (uniform(rng) < 0.02) {
      const double y = std::round(with_outliers.predicted_mm[k] + 200.0 * (uniform(rng) - 0.5));
      with_outliers.residual[k] = y - with_outliers.predicted_mm[k];
      ++outliers;
    }
  }
  MixtureParameters broad;  // the two-mode fit: both lasing modes in one, the outliers in one
  broad.mean = Eigen::Vector2d(0.2, 3.1);
  broad.variance = Eigen::Vector2d(1.7 * 1.7, 47.0 * 47.0);
  broad.weight = Eigen::Vector2d(0.985, 0.015);
  const Diagnosis o = diagnose_residuals(with_outliers, broad, rounded(0));
  const Finding& found = finding(o, EffectKind::Outliers);
  EXPECT_EQ(o.lasing_modes, (std::vector<int>{0}));
  EXPECT_TRUE(found.significant);
  // Beyond 8 robust σ (about 14 mm) of the lasing mode: most of the 2 % spread over ±100 mm.
  EXPECT_GT(found.result.statistic, 0.7 * outliers);
  EXPECT_LE(found.result.statistic, outliers);
}

// The draws' seeds follow from one seed and the draw's index: any runner gives the serial result.
TEST(ResidualDiagnosis, IsTheSameOnAnyNumberOfThreads) {
  const MixtureParameters modes = overlapping_modes();
  const DiagnosisInput in = rounded_record(9, modes, Extra::None);
  const Diagnosis serial = diagnose_residuals(in, modes, rounded(16));
  DiagnosisOptions options = rounded(16);
  options.parallel = [](int count, const std::function<void(int)>& task) {
    std::vector<std::thread> threads;
    for (int i = 0; i < count; ++i) threads.emplace_back(task, i);
    for (auto& t : threads) t.join();
  };
  const Diagnosis parallel = diagnose_residuals(in, modes, options);
  ASSERT_EQ(serial.findings.size(), parallel.findings.size());
  for (std::size_t i = 0; i < serial.findings.size(); ++i) {
    EXPECT_EQ(serial.findings[i].kind, parallel.findings[i].kind);
    EXPECT_EQ(serial.findings[i].result.p_value, parallel.findings[i].result.p_value);
    const double a = serial.findings[i].null_mean, b = parallel.findings[i].null_mean;
    EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << effect_name(serial.findings[i].kind);
  }
}

TEST(ResidualDiagnosis, RefusesARoundingWithoutPredictedRanges) {
  const MixtureParameters modes = overlapping_modes();
  DiagnosisInput in = rounded_record(2, modes, Extra::None);
  in.predicted_mm.resize(0);
  EXPECT_THROW(diagnose_residuals(in, modes, rounded(4)), InvalidInput);
  DiagnosisOptions negative = rounded(4);
  negative.resolution_mm = -1.0;
  in = rounded_record(2, modes, Extra::None);
  EXPECT_THROW(diagnose_residuals(in, modes, negative), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
