// The tables behind the figures of the search's terms (cli/term_figure_tables.hpp): a kept
// term's curve is the term as the calibration holds it, the partial residual adds back the term's
// own contribution where it acts, the bins carry the fitted values, the runs the chain's law,
// and the density is a density.
#include "cli/term_figure_tables.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace tofcomp::cli {
namespace {

// A CSV table as columns of numbers (an empty cell is NaN).
std::map<std::string, std::vector<double>> parse_csv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::istringstream head(line);
  for (std::string name; std::getline(head, name, ',');) header.push_back(name);
  std::map<std::string, std::vector<double>> out;
  while (std::getline(in, line)) {
    std::istringstream row(line + ",");
    for (const std::string& name : header) {
      std::string cell;
      std::getline(row, cell, ',');
      out[name].push_back(cell.empty() ? std::nan("") : std::stod(cell));
    }
  }
  return out;
}

core::MixtureParameters two_modes() {
  core::MixtureParameters m;
  m.mean = Eigen::Vector2d(-2.0, 2.0);
  m.variance = Eigen::Vector2d(0.25, 1.0);
  m.weight = Eigen::Vector2d(0.6, 0.4);
  return m;
}

// Ten ranges a second apart, the junction at 0..9 °C, t_on = 0..9 s; modes 0 0 0 1 1 0 1 1 1 1;
// e = 0.1·k (mode 0) and −0.2·k (mode 1).
SearchResiduals ten_ranges(const core::ExtendedMixture& mixture) {
  core::CovariateSeries series;
  series.time_s = Eigen::VectorXd::LinSpaced(10, 0.0, 9.0);
  series.junction_c = series.time_s;
  series.time_since_power_on_s = series.time_s;
  calibration::Compensation compensation;
  compensation.bias_mm = Eigen::VectorXd::Zero(10);
  compensation.noise_state = Eigen::VectorXi::Zero(10);
  SearchResiduals r{compensation, core::CovariateTable(series), mixture, {}, {}, {}, {}};
  r.mode.resize(10);
  r.mode << 0, 0, 0, 1, 1, 0, 1, 1, 1, 1;
  r.responsibility = Eigen::MatrixXd::Zero(10, 2);  // certain of each range's mode
  for (int k = 0; k < 10; ++k) r.responsibility(k, r.mode[k]) = 1.0;
  r.e.resize(10);
  r.residual.resize(10);
  for (int k = 0; k < 10; ++k) {
    r.e[k] = r.mode[k] == 0 ? 0.1 * k : -0.2 * k;
    r.residual[k] = r.e[k] + mixture.modes.mean[r.mode[k]];
  }
  return r;
}

core::MeanTermFit warm_up(double gamma_mm, double tau_s) {
  core::Term t;
  t.parameter = core::Parameter::Bias;
  t.covariate = core::Covariate::TimeSincePowerOn;
  t.form = core::Form::Decay;
  t.time_constant_s = tau_s;
  return {t, Eigen::VectorXd::Constant(1, gamma_mm)};
}

TEST(TermFigureTables, TheCurveIsTheFittedTerm) {
  const SearchResiduals r = ten_ranges(core::without_extensions(two_modes()));
  const auto curve = parse_csv(mean_term_curve_csv(r, warm_up(2.87, 278.0)));
  ASSERT_GT(curve.at("covariate").size(), 100u);
  EXPECT_DOUBLE_EQ(curve.at("covariate").front(), 0.0);
  EXPECT_DOUBLE_EQ(curve.at("covariate").back(), 9.0);
  for (std::size_t i = 0; i < curve.at("covariate").size(); ++i) {
    EXPECT_NEAR(curve.at("fitted_mm")[i], 2.87 * std::exp(-curve.at("covariate")[i] / 278.0),
                1e-12);
  }
}

TEST(TermFigureTables, PartialResidualAddsBackTheTermWhereItActs) {
  const SearchResiduals r = ten_ranges(core::without_extensions(two_modes()));
  const core::MeanTermFit fit = warm_up(3.0, 5.0);
  const auto bias = parse_csv(mean_term_ranges_csv(r, fit.term, &fit));
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(bias.at("in_term")[k], 1.0);
    EXPECT_NEAR(bias.at("partial_residual_mm")[k], r.e[k] + 3.0 * std::exp(-k / 5.0), 1e-12);
  }
  // A candidate not kept: its residual as it is.
  const auto candidate = parse_csv(mean_term_ranges_csv(r, fit.term, nullptr));
  EXPECT_NEAR(candidate.at("partial_residual_mm")[4], r.e[4], 1e-12);
  // Mode 2's offset: only its ranges.
  core::MeanTermFit offset = fit;
  offset.term.parameter = core::Parameter::ModeOffset;
  offset.term.mode = 1;
  const auto mode = parse_csv(mean_term_ranges_csv(r, offset.term, &offset));
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(mode.at("in_term")[k], r.mode[k] == 1 ? 1.0 : 0.0) << k;
    EXPECT_EQ(std::isnan(mode.at("partial_residual_mm")[k]), r.mode[k] != 1) << k;
  }
}

TEST(TermFigureTables, BinsCarryTheFittedAndTheObserved) {
  core::NoiseBins bins;
  bins.term.parameter = core::Parameter::Spread;
  bins.term.covariate = core::Covariate::JunctionTemperature;
  bins.term.form = core::Form::Bins;
  bins.term.knots = Eigen::VectorXd::Constant(1, 4.5);
  bins.table.resize(2, 2);
  bins.table << 0.04, 0.09, 0.16, 0.25;
  const SearchResiduals r = ten_ranges(core::without_extensions(two_modes()));
  const auto t = parse_csv(bins_term_csv(r, bins.term, &bins));
  ASSERT_EQ(t.at("bin").size(), 4u);  // 2 bins × 2 modes
  EXPECT_EQ(t.at("low")[0], 0.0);
  EXPECT_EQ(t.at("high")[0], 4.5);
  EXPECT_EQ(t.at("high")[3], 9.0);
  EXPECT_NEAR(t.at("fitted")[0], 0.2, 1e-12);
  EXPECT_NEAR(t.at("fitted")[3], 0.5, 1e-12);
  EXPECT_EQ(t.at("ranges")[0], 3.0);             // bin 1 (0..4 °C): ranges 0, 1, 2 of mode 1
  EXPECT_TRUE(std::isnan(t.at("observed")[0]));  // fewer than ten ranges
  EXPECT_TRUE(std::isnan(t.at("held")[0]));
  // One bin of all ten ranges: the share of each mode by its posteriors.
  core::Term weights = bins.term;
  weights.parameter = core::Parameter::Weights;
  weights.knots = Eigen::VectorXd::Constant(1, 100.0);
  const auto shares = parse_csv(bins_term_csv(r, weights, nullptr));
  EXPECT_NEAR(shares.at("observed")[0], 0.4, 1e-12);
  EXPECT_NEAR(shares.at("observed")[1], 0.6, 1e-12);
  EXPECT_NEAR(shares.at("held")[1], 0.4, 1e-12);
  // Not kept: no fitted values, the model's single σ instead.
  const auto held = parse_csv(bins_term_csv(r, bins.term, nullptr));
  EXPECT_TRUE(std::isnan(held.at("fitted")[1]));
  EXPECT_NEAR(held.at("held")[1], 1.0, 1e-12);
}

TEST(TermFigureTables, RunsUnderTheChainAndUnderIndependentDraws) {
  core::ExtendedMixture chain = core::without_extensions(two_modes());
  chain.transition.resize(2, 2);
  chain.transition << 0.8, 0.2, 0.3, 0.7;
  const SearchResiduals r = ten_ranges(chain);
  const auto runs = parse_csv(runs_csv(r, &chain.transition));
  // Mode 1: runs of 3 and 1; mode 2: runs of 2 and 4. Four lengths shown per mode.
  ASSERT_EQ(runs.at("mode").size(), 8u);
  EXPECT_EQ(runs.at("observed")[0], 1.0);  // mode 1, length 1
  EXPECT_EQ(runs.at("observed")[2], 1.0);  // mode 1, length 3
  EXPECT_EQ(runs.at("observed")[7], 1.0);  // mode 2, length 4
  EXPECT_NEAR(runs.at("chain")[2], 2.0 * 0.2 * 0.8 * 0.8, 1e-12);
  EXPECT_NEAR(runs.at("independent")[5], 2.0 * 0.6 * 0.4, 1e-12);  // mode 2, length 2
  const auto independent = parse_csv(runs_csv(r, nullptr));
  EXPECT_TRUE(std::isnan(independent.at("chain")[0]));
}

TEST(TermFigureTables, TheDensityIsADensity) {
  core::ExtendedMixture outliers = core::without_extensions(two_modes());
  outliers.outlier_weight = 0.1;
  outliers.outlier_density = 1.0 / 200.0;
  const SearchResiduals r = ten_ranges(outliers);
  const auto d = parse_csv(density_csv(r));
  const std::vector<double>& x = d.at("residual_mm");
  double gaussian = 0.0;
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double dx = x[i] - x[i - 1];
    gaussian += 0.5 * dx *
                (d.at("mode1")[i] + d.at("mode1")[i - 1] + d.at("mode2")[i] + d.at("mode2")[i - 1]);
    EXPECT_NEAR(d.at("total")[i], d.at("mode1")[i] + d.at("mode2")[i] + 0.1 / 200.0, 1e-12);
    EXPECT_DOUBLE_EQ(d.at("outliers")[i], 0.1 / 200.0);
  }
  EXPECT_NEAR(gaussian, 0.9, 1e-3);  // (1 − ε) of the mass in the modes
}

}  // namespace
}  // namespace tofcomp::cli
