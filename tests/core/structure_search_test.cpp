#include "core/structure_search.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "core/error.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

using testing::cubic_bias;
using testing::kSyntheticDistanceMm;

double linear_bias(double t) {
  return 1.5 * (t - 26.8);
}

StructureChoice search_on(const testing::SyntheticMeasurements& data,
                          StructureSearchOptions options = {}) {
  options.max_fourier_order = 0;  // the polynomial family alone unless a test asks for both
  return search_structure(data.junction_temperature_c, data.range.array() - kSyntheticDistanceMm,
                          options);
}

// Three well separated modes and a cubic bias: the search finds three modes and an order that
// follows the cubic, and the chosen model's mode curves H(t)θ + μ_i match the truth.
TEST(StructureSearch, FindsThreeModesAndACubicBias) {
  const auto truth = testing::mixture({-4.0, 0.0, 4.5}, {0.8, 0.7, 0.9}, {0.3, 0.3, 0.4});
  const auto data = testing::draw_measurements(testing::cycling_temperature(30000),
                                               kSyntheticDistanceMm, cubic_bias, truth, 3);
  const StructureChoice choice = search_on(data);
  EXPECT_EQ(choice.modes, 3);
  ASSERT_EQ(choice.basis.terms().size(), 1u);
  EXPECT_GE(choice.basis.terms()[0].order, 3);
  EXPECT_LE(choice.basis.terms()[0].order, 6);
  const Eigen::VectorXd grid = Eigen::VectorXd::LinSpaced(9, 25.0, 28.6);
  const Eigen::VectorXd bias = choice.basis.design_matrix(grid) * choice.fit.theta;
  for (Eigen::Index g = 0; g < grid.size(); ++g) {
    EXPECT_NEAR(bias[g] + choice.fit.mixture.mean[1], cubic_bias(grid[g]) + truth.mean[1], 0.1)
        << grid[g] << " °C";
  }
  // The evidence is there for every candidate visited, the chosen one among them.
  EXPECT_TRUE(choice.candidates[static_cast<std::size_t>(choice.chosen)].ok);
  EXPECT_GE(choice.best_by_glr, 0);
  EXPECT_GE(choice.best_by_bic, 0);
}

// One Gaussian around a straight line: the one-standard-error rule keeps the model small, where
// GLR (Algorithm 2) takes the largest candidate it saw.
TEST(StructureSearch, KeepsTheSmallestModelThatPredictsAsWell) {
  const auto truth = testing::mixture({0.0}, {2.0}, {1.0});
  const auto data = testing::draw_measurements(testing::cycling_temperature(20000),
                                               kSyntheticDistanceMm, linear_bias, truth, 5);
  const StructureChoice choice = search_on(data);
  EXPECT_EQ(choice.modes, 1);
  EXPECT_LE(choice.basis.terms()[0].order, 2);
  const CandidateEvidence& by_glr = choice.candidates[static_cast<std::size_t>(choice.best_by_glr)];
  const CandidateEvidence& chosen = choice.candidates[static_cast<std::size_t>(choice.chosen)];
  EXPECT_GT(by_glr.parameters, chosen.parameters);
}

// A basis the user fixed is kept; only the number of modes is searched at it.
TEST(StructureSearch, SearchesOnlyTheModesAtAGivenBasis) {
  const auto truth = testing::mixture({-2.5, 2.5}, {0.8, 0.8}, {0.5, 0.5});
  const auto data = testing::draw_measurements(testing::cycling_temperature(10000),
                                               kSyntheticDistanceMm, cubic_bias, truth, 9);
  StructureSearchOptions options;
  options.basis = Basis::polynomial(3, data.junction_temperature_c);
  const StructureChoice choice = search_on(data, options);
  EXPECT_EQ(choice.modes, 2);
  EXPECT_EQ(choice.basis.describe(), options.basis->describe());
  for (const CandidateEvidence& e : choice.candidates) EXPECT_EQ(e.family, "given");
  EXPECT_EQ(static_cast<int>(choice.candidates.size()), options.max_modes);
}

// The Fourier family is searched too, and a bias that is one period of a sine over the range
// (which Eq. 11 at f0 = 1 / (2 × span) holds in two terms) is followed by whichever family wins.
TEST(StructureSearch, SearchesTheFourierFamilyBeside) {
  const auto truth = testing::mixture({-2.0, 2.0}, {0.7, 0.7}, {0.5, 0.5});
  const auto data = testing::draw_measurements(
      testing::cycling_temperature(20000), kSyntheticDistanceMm,
      [](double t) { return 3.0 * std::sin(2.0 * 3.14159265358979 * (t - 24.8) / 4.0); }, truth,
      13);
  StructureSearchOptions options;
  const StructureChoice choice = search_structure(
      data.junction_temperature_c, data.range.array() - kSyntheticDistanceMm, options);
  bool fourier_seen = false;
  for (const CandidateEvidence& e : choice.candidates) fourier_seen |= e.family == "fourier";
  EXPECT_TRUE(fourier_seen);
  // The fitted bias follows the true one up to a constant (which the mode offsets carry).
  const Eigen::VectorXd fitted =
      choice.basis.design_matrix(data.junction_temperature_c) * choice.fit.theta;
  const Eigen::VectorXd gap = fitted - data.true_bias;
  const double spread = std::sqrt((gap.array() - gap.mean()).square().mean());
  EXPECT_LT(spread, 0.05);
}

// The folds' fits run through options.parallel_for: on threads, in reverse order or one after
// the other, every candidate's evidence and the choice are the same bit for bit.
TEST(StructureSearch, GivesTheSameChoiceWhateverRunsTheFolds) {
  const auto truth = testing::mixture({-2.5, 0.0, 2.5}, {0.8, 0.6, 0.8}, {0.3, 0.4, 0.3});
  const auto data = testing::draw_measurements(testing::cycling_temperature(8000),
                                               kSyntheticDistanceMm, cubic_bias, truth, 21);
  StructureSearchOptions serial;
  serial.max_polynomial_order = 5;
  serial.max_modes = 3;
  StructureSearchOptions threaded = serial;
  threaded.parallel_for = [](int count, const std::function<void(int)>& task) {
    std::vector<std::thread> threads;
    for (int i = 0; i < count; ++i) threads.emplace_back(task, i);
    for (std::thread& t : threads) t.join();
  };
  StructureSearchOptions reversed = serial;
  reversed.parallel_for = [](int count, const std::function<void(int)>& task) {
    for (int i = count - 1; i >= 0; --i) task(i);
  };
  const StructureChoice a = search_on(data, serial);
  for (const StructureSearchOptions& options : {threaded, reversed}) {
    const StructureChoice b = search_on(data, options);
    ASSERT_EQ(a.candidates.size(), b.candidates.size());
    for (std::size_t i = 0; i < a.candidates.size(); ++i) {
      const CandidateEvidence &x = a.candidates[i], &y = b.candidates[i];
      EXPECT_EQ(x.name, y.name);
      EXPECT_EQ(x.ok, y.ok);
      EXPECT_EQ(x.log_likelihood, y.log_likelihood) << x.name;
      EXPECT_EQ(x.held_out_log_likelihood, y.held_out_log_likelihood) << x.name;
      EXPECT_EQ(x.block_log_likelihood, y.block_log_likelihood) << x.name;
    }
    EXPECT_EQ(a.chosen, b.chosen);
    EXPECT_EQ(a.basis.describe(), b.basis.describe());
    EXPECT_EQ(a.modes, b.modes);
    EXPECT_EQ(a.fit.theta, b.fit.theta);
    EXPECT_EQ(a.shortfall_per_range, b.shortfall_per_range);
  }
  EXPECT_GT(a.candidates.size(), 3u);
}

TEST(StructureSearch, RefusesTooFewRangesOrFolds) {
  const auto truth = testing::mixture({0.0}, {1.0}, {1.0});
  const auto data = testing::draw_measurements(testing::cycling_temperature(60),
                                               kSyntheticDistanceMm, linear_bias, truth, 1);
  EXPECT_THROW(search_on(data), InvalidInput);
  StructureSearchOptions one_fold;
  one_fold.folds = 1;
  EXPECT_THROW(search_on(data, one_fold), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
