// Gross errors (calibration/gross_errors.hpp): spurious returns far beyond any lasing mode are
// set apart before Eq. 8 is fitted and carried as the outlier component. Known by construction:
// the ranges injected beyond the bound are exactly those set apart; training on a twin record
// with a cluster of spurious returns a metre beyond the target keeps its lasing modes within
// the device's scale and carries the injected share; the model search starts from that component
// and lists it first; and a clean record is trained as before, with no extension.
#include "calibration/gross_errors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "calibration/model_search.hpp"
#include "calibration/plausibility.hpp"
#include "calibration/training.hpp"
#include "core/extended_mixture.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/paper_structure_settings.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/synthetic_measurements.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

constexpr double kDistanceMm = 3000.0;
// The injected spurious returns: this share of the ranges, this far beyond the target, this wide.
constexpr double kSpuriousShare = 0.02;
constexpr double kSpuriousOffsetMm = 1200.0;
constexpr double kSpuriousStdMm = 15.0;

MeasuredData ranges_at(const std::vector<double>& errors_mm) {
  MeasuredData d;
  d.source = "synthetic";
  const auto n = static_cast<Eigen::Index>(errors_mm.size());
  d.range_time_s = Eigen::VectorXd::LinSpaced(n, 0.0, static_cast<double>(n - 1));
  d.range_mm.resize(n);
  d.true_range_mm = Eigen::VectorXd::Constant(n, kDistanceMm);
  for (Eigen::Index k = 0; k < n; ++k)
    d.range_mm[k] = kDistanceMm + errors_mm[static_cast<std::size_t>(k)];
  d.has_true_range.assign(errors_mm.size(), true);
  d.range_line.assign(errors_mm.size(), 0);
  return d;
}

TEST(GrossErrors, AreTheRangesBeyondTheLargestLasingError) {
  ASSERT_DOUBLE_EQ(kGrossErrorMm, 80.0);  // 50 mm predicted error + 6 × 5 mm statistical error
  const GrossErrors g = find_gross_errors(ranges_at({1.0, -3.0, 1200.0, 79.0, -80.5, 4.0, -12.0}));
  EXPECT_EQ(g.count, 2);
  EXPECT_EQ(g.ranges, 7);
  EXPECT_EQ(g.kept, (std::vector<Eigen::Index>{0, 1, 3, 5, 6}));
  EXPECT_NEAR(g.share(), 2.0 / 7.0, 1e-15);
}

TEST(GrossErrors, NoneWhenMostRangesMissTheReference) {
  // A reference distance half a metre off: the distance is wrong, not the ranges.
  const GrossErrors g = find_gross_errors(ranges_at({500.0, 502.0, 1.0, 498.0}));
  EXPECT_EQ(g.count, 0);
  EXPECT_EQ(g.kept.size(), 4u);
}

core::MixtureParameters two_modes() {
  return testing::mixture({-2.0, 2.0}, {1.0, 1.5}, {0.4, 0.6});
}

TEST(GrossErrors, ExtensionIsTheOutlierComponentOverTheResiduals) {
  const core::MixtureParameters modes = two_modes();
  EXPECT_FALSE(gross_error_extension(modes, 0.0, Eigen::Vector3d(-1.0, 0.0, 1.0)));
  Eigen::VectorXd residual(5);
  residual << -2.5, 2.0, 1.0, -10.0 + 9.0, 1190.0;
  const auto e = gross_error_extension(modes, 0.2, residual);
  ASSERT_TRUE(e);
  ASSERT_EQ(e->effects.size(), 1u);
  EXPECT_EQ(e->effects[0].parameter, core::Parameter::Outliers);
  EXPECT_TRUE(e->mean_terms.empty());
  // One gross error in five: the lasing ranges add about a thousandth each (the uniform density
  // 1 / 1192.5 mm against the modes' ~0.1 / mm).
  EXPECT_NEAR(e->extended_mixture.outlier_weight, 0.2, 0.01);
  EXPECT_DOUBLE_EQ(e->extended_mixture.outlier_density, 1.0 / 1192.5);
  EXPECT_EQ(e->extended_mixture.modes.mean, modes.mean);
}

TEST(GrossErrors, TheOutlierWeightTakesInTheOutliersAmongTheModes) {
  // 2 % of the ranges uniform over ±100 mm: a fifth of them beyond 80 mm, the rest among the
  // modes. From the share beyond, EM on the weight finds them all.
  constexpr double kShare = 0.02, kHalfWidthMm = 100.0;
  constexpr int kResidualRanges = 40000;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const core::MixtureParameters modes = two_modes();
  Eigen::VectorXd residual(kResidualRanges);
  int beyond = 0, outliers = 0;
  for (int k = 0; k < kResidualRanges; ++k) {
    if (unit(rng) < kShare) {
      residual[k] = kHalfWidthMm * (2.0 * unit(rng) - 1.0);
      ++outliers;
      beyond += std::abs(residual[k]) > kGrossErrorMm;
    } else {
      const int i = unit(rng) < modes.weight[0] ? 0 : 1;
      residual[k] = modes.mean[i] + std::sqrt(modes.variance[i]) * normal(rng);
    }
  }
  residual[0] = -kHalfWidthMm, residual[1] = kHalfWidthMm;  // the span the generator drew over
  core::ExtendedMixture start = core::without_extensions(modes);
  start.outlier_density = 1.0 / (2.0 * kHalfWidthMm);
  start.outlier_weight = static_cast<double>(beyond) / kResidualRanges;
  const double fitted = fit_outlier_weight(residual, start);
  const double truth = static_cast<double>(outliers) / kResidualRanges;
  EXPECT_LT(start.outlier_weight, 0.5 * truth);
  // Those within a few σ of a mode cannot be told from it: a few percent of the outliers.
  EXPECT_NEAR(fitted, truth, 0.1 * truth);
}

// The paper's structure, fixed, so that the test is about the gross errors and quick.
TrainSettings fixed_structure() {
  return test::paper_structure_settings();
}

MeasuredData seeded_default_record() {
  sim::Scenario scenario =
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/default.yaml");
  scenario.seed = 11;
  return test::twin_measured_data(scenario);
}

// Replaces a share of the ranges, drawn at random, by spurious returns; returns how many.
Eigen::Index inject_spurious_returns(MeasuredData& data, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> spread(kSpuriousOffsetMm, kSpuriousStdMm);
  Eigen::Index injected = 0;
  for (Eigen::Index k = 0; k < data.range_mm.size(); ++k) {
    if (unit(rng) < kSpuriousShare) {
      data.range_mm[k] = std::round(data.true_range_mm[k] + spread(rng));
      ++injected;
    }
  }
  return injected;
}

TEST(GrossErrors, TrainingKeepsTheLasingModesAndCarriesTheShare) {
  MeasuredData data = seeded_default_record();
  const Training clean = train_calibration(data, fixed_structure());
  EXPECT_EQ(clean.gross_errors.count, 0);
  EXPECT_FALSE(clean.calibration.extension);

  const Eigen::Index injected = inject_spurious_returns(data, 5);
  ASSERT_GT(injected, 100);
  const Training t = train_calibration(data, fixed_structure());
  EXPECT_EQ(t.gross_errors.count, injected);
  EXPECT_EQ(t.junction.junction_c.size(), data.range_mm.size());  // every range, as callers need
  EXPECT_TRUE(implausibilities(t.calibration).empty()) << implausibilities(t.calibration).front();
  for (Eigen::Index i = 0; i < t.calibration.model.mixture.modes(); ++i) {
    // The lasing modes as trained without the spurious returns (they change by the few lasing
    // ranges the injection replaced).
    EXPECT_NEAR(t.calibration.model.mixture.mean[i], clean.calibration.model.mixture.mean[i], 0.1);
  }
  ASSERT_TRUE(t.calibration.extension);
  // Every injected return is beyond the bound; the lasing modes' far tails add a little.
  const double share = static_cast<double>(injected) / static_cast<double>(data.range_mm.size());
  EXPECT_GE(t.calibration.extension->extended_mixture.outlier_weight, share);
  EXPECT_NEAR(t.calibration.extension->extended_mixture.outlier_weight, share, 0.05 * share);
}

TEST(GrossErrors, TheModelSearchStartsFromTheOutlierComponent) {
  MeasuredData data = seeded_default_record();
  inject_spurious_returns(data, 6);
  const Training t = train_calibration(data, fixed_structure());
  ModelSearchOptions options;
  options.max_steps = 1;
  const ModelSearchResult r = search_model(data, t.calibration, t.junction, options);
  EXPECT_EQ(r.carried_from_training, 1);
  ASSERT_FALSE(r.kept.empty());
  EXPECT_EQ(r.kept.front().parameter, core::Parameter::Outliers);
  ASSERT_TRUE(r.calibration.extension);
  EXPECT_GT(r.calibration.extension->extended_mixture.outlier_weight, 0.0);
  // No step named the outliers again: the component was in every model compared.
  for (const SearchStep& s : r.steps) {
    for (const CandidateResult& c : s.candidates) {
      EXPECT_NE(c.term.parameter, core::Parameter::Outliers);
    }
  }
}

}  // namespace
}  // namespace tofcomp::calibration

namespace tofcomp::calibration {
namespace {

// The twin's outliers scenario: 2 % of the ranges uniform within ±100 mm, a fifth of them beyond
// the bound. Training carries those with the modes held (the rest widen the modes); the search's
// fit of the carried component with every parameter on all the ranges finds nearly all 2 %.
TEST(GrossErrors, TheSearchFitsTheCarriedComponentWithTheModes) {
  constexpr double kTwinOutlierShare = 0.02;  // config/scenarios/effect-outliers.yaml
  sim::Scenario scenario =
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/effect-outliers.yaml");
  scenario.seed = 4;
  const MeasuredData data = test::twin_measured_data(scenario);
  const Training t = train_calibration(data, fixed_structure());
  ASSERT_TRUE(t.calibration.extension);
  const double trained = t.calibration.extension->extended_mixture.outlier_weight;
  ModelSearchOptions options;
  options.max_steps = 1;
  const ModelSearchResult r = search_model(data, t.calibration, t.junction, options);
  ASSERT_TRUE(r.calibration.extension);
  const double searched = r.calibration.extension->extended_mixture.outlier_weight;
  EXPECT_LT(trained, 0.75 * kTwinOutlierShare);
  EXPECT_NEAR(searched, kTwinOutlierShare, 0.25 * kTwinOutlierShare);
}

}  // namespace
}  // namespace tofcomp::calibration
