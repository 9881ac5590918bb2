#include "io/calibration_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/yaml_fields.hpp"
#include "tests/support/file_text.hpp"

namespace tofcomp::io {
namespace {

core::Calibration example() {
  core::Calibration c;
  c.thermal = {0.18, 0.5, 60.0, 2000.0, 10.0};
  c.ambient_c = 21.5;
  c.model.basis = core::Basis(
      {core::BasisTerm{core::BasisKind::Polynomial, 3, core::PolynomialForm::Legendre, 0.0},
       core::BasisTerm{core::BasisKind::Fourier, 2, core::PolynomialForm::Legendre, 0.1}},
      core::TemperatureScaling{26.8, 2.0});
  c.model.theta = Eigen::VectorXd::LinSpaced(7, -1.0 / 3.0, 2.0 / 7.0);
  c.model.mixture.mean = Eigen::Vector2d(-2.0000000000000004, 2.5);
  c.model.mixture.variance = Eigen::Vector2d(0.81, 1.21);
  c.model.mixture.weight = Eigen::Vector2d(0.55, 0.45);
  c.provenance = {"data.csv", "2026-11-22T00:00:00Z", "tofcomp 0.1.0", 20000, "beam 0"};
  return c;
}

// A file of this test's own: ctest runs the tests of this file as processes at once, and two
// that wrote one shared broken.yaml read each other's.
std::string temp_file(const std::string& name) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return ::testing::TempDir() + "/" + test->test_suite_name() + "." + test->name() + "." + name;
}

TEST(CalibrationFile, RoundTripIsExact) {
  const std::string file = temp_file("calibration.yaml");
  const core::Calibration c = example();
  write_calibration_file(file, c);
  const core::Calibration back = read_calibration_file(file);
  EXPECT_EQ(back.model.theta, c.model.theta);
  EXPECT_EQ(back.model.mixture.mean, c.model.mixture.mean);
  EXPECT_EQ(back.model.mixture.variance, c.model.mixture.variance);
  EXPECT_EQ(back.model.mixture.weight, c.model.mixture.weight);
  EXPECT_EQ(back.model.basis.describe(), c.model.basis.describe());
  EXPECT_EQ(back.model.basis.scaling().half_range_c, 2.0);
  EXPECT_EQ(back.thermal.c2_j_per_k, 2000.0);
  EXPECT_EQ(back.ambient_c, 21.5);
  EXPECT_EQ(back.kalman_noise.measurement_variance_k2, c.kalman_noise.measurement_variance_k2);
  EXPECT_EQ(back.provenance.samples, 20000);
  // A second write of what was read is byte-identical.
  write_calibration_file(temp_file("calibration2.yaml"), back);
  EXPECT_EQ(testing::file_text(file), testing::file_text(temp_file("calibration2.yaml")));
  // The same bias at any temperature.
  EXPECT_EQ(back.model.bias_at(27.3), c.model.bias_at(27.3));
}

std::string error_of(const std::string& text) {
  const std::string file = temp_file("broken.yaml");
  std::ofstream(file) << text;
  try {
    read_calibration_file(file);
  } catch (const YamlSchemaError& e) {
    return e.what();
  }
  return "no error";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The trained junction range is optional: absent it stays absent (a file from before it existed
// reads as it did); present it round-trips, and a range with min above max is refused.
TEST(CalibrationFile, TrainedJunctionRangeRoundTrips) {
  const std::string file = temp_file("calibration-range.yaml");
  core::Calibration c = example();
  write_calibration_file(file, c);
  EXPECT_FALSE(read_calibration_file(file).model.trained_junction_c.has_value());
  EXPECT_EQ(testing::file_text(file).find("trained_junction_c"), std::string::npos);
  c.model.trained_junction_c = core::TemperatureRange{24.8125, 28.6875};
  write_calibration_file(file, c);
  const core::Calibration back = read_calibration_file(file);
  ASSERT_TRUE(back.model.trained_junction_c.has_value());
  EXPECT_EQ(back.model.trained_junction_c->min_c, 24.8125);
  EXPECT_EQ(back.model.trained_junction_c->max_c, 28.6875);
  const std::string inverted = replaced(testing::file_text(file), "min: 24.8125", "min: 30");
  std::ofstream(file) << inverted;
  EXPECT_THROW(read_calibration_file(file), YamlSchemaError);
}

TEST(CalibrationFile, ErrorsNameTheFileAndKey) {
  const std::string good = calibration_to_yaml(example());
  EXPECT_NE(error_of(replaced(good, "version: 2", "version: 3")).find("version is 3"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, "schema: tofcomp-calibration", "schema: other"))
                .find("schema must be tofcomp-calibration"),
            std::string::npos);
  EXPECT_NE(
      error_of(replaced(good, "  power_w:", "  powr_w:")).find("thermal.powr_w is not a known key"),
      std::string::npos);
  EXPECT_NE(error_of(replaced(good, "  r1_k_per_w: 0.17999999999999999\n", ""))
                .find("thermal.r1_k_per_w is missing"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, "weight: 0.45", "weight: 0.5")).find("sum to"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, "theta_mm: [", "theta_mm: [1, ")).find("θ has 8"),
            std::string::npos);
  const std::string message = error_of("schema: [");
  EXPECT_EQ(message.rfind(temp_file("broken.yaml"), 0), 0u) << message;
}

// What training chose from the data, and its evidence, survive the file; a file without the
// section (written before it existed, or with every choice given) reads as no choice made.
TEST(CalibrationFile, TrainingChoicesRoundTrip) {
  const std::string file = temp_file("calibration-choices.yaml");
  core::Calibration c = example();
  write_calibration_file(file, c);
  EXPECT_EQ(testing::file_text(file).find("choices"), std::string::npos);
  EXPECT_FALSE(read_calibration_file(file).choices.structure.has_value());
  c.choices.kalman_noise = core::KalmanNoiseRecord{"innovations", {"junction_process"}};
  c.choices.structure =
      core::StructureRecord{"held-out",
                            "polynomial(3, legendre), 2 modes",
                            "polynomial(9, legendre), 2 modes",
                            "polynomial(4, legendre), 2 modes",
                            {{"polynomial(3, legendre), 2 modes", 8, -2.25, 35853.5, 435836.25},
                             {"polynomial(9, legendre), 2 modes", 14, -2.2501, 35900.0, 435900.0}}};
  c.choices.junction_dynamics =
      core::JunctionDynamicsRecord{"ranges", true, 4.25, 31.5, 1.875, 10.8, 0.0125, true};
  write_calibration_file(file, c);
  const core::Calibration back = read_calibration_file(file);
  ASSERT_TRUE(back.choices.kalman_noise && back.choices.structure &&
              back.choices.junction_dynamics);
  const core::JunctionDynamicsRecord& j = *back.choices.junction_dynamics;
  EXPECT_TRUE(j.from_ranges);
  EXPECT_EQ(j.method, "ranges");
  EXPECT_EQ(j.rise_k, 4.25);
  EXPECT_EQ(j.time_constant_s, 31.5);
  EXPECT_EQ(j.case_log_rise_k, 1.875);
  EXPECT_EQ(j.case_log_time_constant_s, 10.8);
  EXPECT_EQ(j.block_p, 0.0125);
  EXPECT_TRUE(j.junction_noise_held);
  // A calibration written before the ranges judged q_j reads as not held.
  const std::string older =
      replaced(testing::file_text(file), "    junction_noise_held: true\n", "");
  ASSERT_NE(older, testing::file_text(file));
  std::ofstream(file) << older;
  EXPECT_FALSE(read_calibration_file(file).choices.junction_dynamics->junction_noise_held);
  write_calibration_file(file, c);
  EXPECT_EQ(back.choices.kalman_noise->held, std::vector<std::string>{"junction_process"});
  const core::StructureRecord& s = *back.choices.structure;
  EXPECT_EQ(s.chosen, "polynomial(3, legendre), 2 modes");
  EXPECT_EQ(s.best_by_bic, "polynomial(4, legendre), 2 modes");
  ASSERT_EQ(s.candidates.size(), 2u);
  EXPECT_EQ(s.candidates[1].parameters, 14);
  EXPECT_EQ(s.candidates[0].bic, 435836.25);
  const std::string broken =
      replaced(testing::file_text(file), "parameters: 14", "parameters: fourteen");
  std::ofstream(file) << broken;
  try {
    read_calibration_file(file);
    ADD_FAILURE() << "a broken candidate was read";
  } catch (const YamlSchemaError& e) {
    EXPECT_NE(std::string(e.what()).find("choices.structure.candidates[1].parameters"),
              std::string::npos)
        << e.what();
  }
}

// A term of the grammar with every field a file can hold set.
core::Term term(core::Parameter p, core::Covariate c, core::Form f) {
  core::Term t;
  t.parameter = p;
  t.covariate = c;
  t.form = f;
  return t;
}

// Every part an extension can hold survives the file exactly.
TEST(CalibrationFile, ExtensionRoundTripIsExact) {
  core::Calibration c = example();
  core::ModelExtension e;
  core::Term smooth = term(core::Parameter::Bias, core::Covariate::Time, core::Form::Smooth);
  smooth.knots = (Eigen::VectorXd(5) << 0.1, 1.0 / 3.0, 2.5, 4.0, 6.75).finished();
  core::Term offset =
      term(core::Parameter::ModeOffset, core::Covariate::JunctionTemperature, core::Form::Linear);
  offset.mode = 1;
  offset.centre = 26.125;
  offset.scale = 1.0 / 7.0;
  offset.covariate_low = 24.5;
  offset.covariate_high = 28.0 + 1.0 / 3.0;
  core::Term lag = term(core::Parameter::Bias, core::Covariate::JunctionLag, core::Form::Linear);
  lag.time_constant_s = 1000.0 / 3.0;
  lag.scale = 0.25;
  e.effects = {smooth.label(),
               offset.label(),
               lag.label(),
               {core::Parameter::Weights, core::Covariate::TimeSincePowerOn},
               {core::Parameter::Spread, core::Covariate::JunctionTemperature},
               {core::Parameter::Outliers, core::Covariate::None}};
  e.mean_terms = {{smooth, (Eigen::VectorXd(4) << 0.5, -1.0 / 3.0, 0.25, 2.0).finished()},
                  {offset, Eigen::VectorXd::Constant(1, 0.1)},
                  {lag, Eigen::VectorXd::Constant(1, -2.0 / 3.0)}};
  e.extended_mixture = core::without_extensions(c.model.mixture);
  core::Term weights =
      term(core::Parameter::Weights, core::Covariate::TimeSincePowerOn, core::Form::Bins);
  weights.knots = Eigen::Vector2d(120.0, 900.5);
  e.extended_mixture.weight_bins =
      core::NoiseBins{weights, Eigen::MatrixXd::Constant(3, 2, 0.5), {}, {}};
  core::Term spread =
      term(core::Parameter::Spread, core::Covariate::JunctionTemperature, core::Form::Bins);
  spread.knots = Eigen::Vector2d(25.5, 27.25);
  e.extended_mixture.variance_bins =
      core::NoiseBins{spread, Eigen::MatrixXd::Constant(3, 2, 0.7), {}, {}};
  e.extended_mixture.variance_bins->table(2, 1) = 1.0 / 7.0;
  e.extended_mixture.outlier_weight = 0.015;
  e.extended_mixture.outlier_density = 1.0 / 180.0;
  c.extension = e;
  const std::string file = temp_file("extended.yaml");
  write_calibration_file(file, c);
  const core::Calibration back = read_calibration_file(file);
  ASSERT_TRUE(back.extension.has_value());
  const core::ModelExtension& x = *back.extension;
  EXPECT_EQ(x.effects, e.effects);
  ASSERT_EQ(x.mean_terms.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const core::Term &a = x.mean_terms[i].term, &b = e.mean_terms[i].term;
    EXPECT_EQ(a.describe(), b.describe());
    EXPECT_EQ(a.mode, b.mode);
    EXPECT_EQ(a.knots, b.knots);
    EXPECT_EQ(a.centre, b.centre);
    EXPECT_EQ(a.scale, b.scale);
    EXPECT_EQ(a.time_constant_s, b.time_constant_s);
    EXPECT_EQ(a.covariate_low, b.covariate_low);  // −∞ and ∞ (no range) stay unbounded
    EXPECT_EQ(a.covariate_high, b.covariate_high);
    EXPECT_EQ(x.mean_terms[i].coefficients, e.mean_terms[i].coefficients);
  }
  EXPECT_EQ(x.extended_mixture.weight_bins->term.covariate, core::Covariate::TimeSincePowerOn);
  EXPECT_EQ(x.extended_mixture.weight_bins->term.knots, weights.knots);
  EXPECT_EQ(x.extended_mixture.weight_bins->table, e.extended_mixture.weight_bins->table);
  EXPECT_EQ(x.extended_mixture.variance_bins->term.knots, spread.knots);
  EXPECT_EQ(x.extended_mixture.variance_bins->table, e.extended_mixture.variance_bins->table);
  EXPECT_EQ(x.extended_mixture.outlier_weight, e.extended_mixture.outlier_weight);
  EXPECT_DOUBLE_EQ(x.extended_mixture.outlier_density, e.extended_mixture.outlier_density);
  EXPECT_EQ(x.extended_mixture.modes.mean, c.model.mixture.mean);
  // The same file again, byte for byte.
  write_calibration_file(temp_file("extended2.yaml"), back);
  EXPECT_EQ(testing::file_text(file), testing::file_text(temp_file("extended2.yaml")));

  // A parametric spread (a decay after power-on): its intercepts and slopes, its table again.
  core::Term decay =
      term(core::Parameter::Spread, core::Covariate::TimeSincePowerOn, core::Form::Decay);
  decay.time_constant_s = 300.0;
  decay.knots.resize(core::kNoiseLevels - 1);
  for (int j = 1; j < core::kNoiseLevels; ++j) decay.knots[j - 1] = 60.0 * j;
  core::ModelExtension slopes;
  slopes.effects = {decay.label()};
  slopes.extended_mixture = core::without_extensions(c.model.mixture);
  slopes.extended_mixture.variance_bins =
      core::NoiseBins{decay, {}, Eigen::Vector2d(-0.25, 0.125), Eigen::Vector2d(0.5, -1.0 / 3.0)};
  slopes.extended_mixture.variance_bins->refresh_table();
  c.extension = slopes;
  write_calibration_file(file, c);
  const core::NoiseBins read =
      *read_calibration_file(file).extension->extended_mixture.variance_bins;
  EXPECT_EQ(read.intercept, slopes.extended_mixture.variance_bins->intercept);
  EXPECT_EQ(read.slope, slopes.extended_mixture.variance_bins->slope);
  EXPECT_EQ(read.table, slopes.extended_mixture.variance_bins->table);
  EXPECT_EQ(read.term.knots, decay.knots);

  core::ModelExtension chain;
  chain.effects = {{core::Parameter::Markov, core::Covariate::None}};
  chain.extended_mixture = core::without_extensions(c.model.mixture);
  chain.extended_mixture.transition = (Eigen::Matrix2d() << 0.875, 0.125, 0.25, 0.75).finished();
  c.extension = chain;
  write_calibration_file(file, c);
  EXPECT_EQ(read_calibration_file(file).extension->extended_mixture.transition,
            chain.extended_mixture.transition);
  // A file without the section is the paper's model.
  EXPECT_FALSE(read_calibration_file([&] {
                 write_calibration_file(file, example());
                 return file;
               }())
                   .extension.has_value());
}

// A version 1 file's one-effect extension loads as the same model in the grammar's terms: its
// covariate in its raw units (hours, °C/min, exp(−t_on/τ)), its bins on the junction temperature.
TEST(CalibrationFile, VersionOneExtensionsStillLoad) {
  const std::string plain = replaced(calibration_to_yaml(example()), "version: 2", "version: 1");
  const std::string file = temp_file("version1.yaml");
  std::ofstream(file) << plain +
                             "extension:\n  effect: warm_up_after_power_on\n  covariate: warm_up\n"
                             "  covariate_mm: 2.5\n  time_constant_s: 300\n";
  core::Calibration c = read_calibration_file(file);
  ASSERT_TRUE(c.extension.has_value());
  ASSERT_EQ(c.extension->mean_terms.size(), 1u);
  EXPECT_EQ(c.extension->mean_terms[0].term.describe(),
            "bias x time_since_power_on (decay, tau = 300 s)");
  EXPECT_EQ(c.extension->mean_terms[0].coefficients[0], 2.5);
  core::CovariatesAt at;
  at.time_since_power_on_s = 300.0;
  EXPECT_NEAR(c.extension->bias_at(at), 2.5 / std::exp(1.0), 1e-12);
  EXPECT_EQ(c.extension->name(), "warm-up after power-on");

  std::ofstream(file) << plain +
                             "extension:\n  effect: temperature_dependent_spread\n"
                             "  covariate: time_h\n  covariate_mm: 0.5\n"
                             "  bin_edges_c: [25, 27]\n"
                             "  bin_variances_mm2: [[1, 2], [3, 4], [5, 6]]\n";
  c = read_calibration_file(file);
  at.time_h = 4.0;
  EXPECT_NEAR(c.extension->bias_at(at), 2.0, 1e-12);  // 0.5 mm/h × 4 h
  at.junction_c = 26.0;
  EXPECT_EQ(c.extension->state_at(at), 1);
  EXPECT_EQ(c.extension->extended_mixture.variance(1, 1), 4.0);
  EXPECT_EQ(c.extension->name(), "temperature-dependent spread");
  // Version 1 keys are not version 2's.
  std::ofstream(file) << replaced(plain, "version: 1", "version: 2") +
                             "extension:\n  effect: outliers\n";
  EXPECT_THROW(read_calibration_file(file), YamlSchemaError);
}

// A linear term's covariate range: two numbers, low then high.
TEST(CalibrationFile, ALinearTermsCovariateRangeIsCheckedWhereItStands) {
  core::Calibration c = example();
  c.extension = core::ModelExtension{};
  core::Term drift = term(core::Parameter::Bias, core::Covariate::Time, core::Form::Linear);
  drift.covariate_low = 0.5;
  drift.covariate_high = 7.25;
  c.extension->effects = {drift.label()};
  c.extension->mean_terms = {{drift, Eigen::VectorXd::Constant(1, 0.25)}};
  c.extension->extended_mixture = core::without_extensions(c.model.mixture);
  const std::string good = calibration_to_yaml(c);
  ASSERT_NE(good.find("covariate_range: [0.5, 7.25]"), std::string::npos) << good;
  const std::string reversed = error_of(replaced(good, "[0.5, 7.25]", "[7.25, 0.5]"));
  EXPECT_NE(reversed.find("extension.terms[0]"), std::string::npos) << reversed;
  EXPECT_NE(reversed.find("low end is not above its high end"), std::string::npos) << reversed;
  const std::string one = error_of(replaced(good, "[0.5, 7.25]", "[0.5]"));
  EXPECT_NE(one.find("extension.terms[0].covariate_range must be two finite numbers"),
            std::string::npos)
      << one;
}

// A smooth term holds as many knots as the search chose (core/effect_grammar.hpp), from 3 to 17:
// nine come back as written, eighteen are refused where they stand.
TEST(CalibrationFile, ASmoothTermsKnotCountIsCheckedWhereItStands) {
  core::Calibration c = example();
  c.extension = core::ModelExtension{};
  core::Term drift = term(core::Parameter::Bias, core::Covariate::Time, core::Form::Smooth);
  drift.knots = Eigen::VectorXd::LinSpaced(9, 0.5, 4.5);
  c.extension->effects = {drift.label()};
  c.extension->mean_terms = {{drift, Eigen::VectorXd::LinSpaced(8, -1.0, 2.5)}};
  c.extension->extended_mixture = core::without_extensions(c.model.mixture);
  const std::string good = calibration_to_yaml(c);
  const std::string file = temp_file("nine-knots.yaml");
  write_calibration_file(file, c);
  const core::Calibration back = read_calibration_file(file);
  ASSERT_TRUE(back.extension.has_value());
  ASSERT_EQ(back.extension->mean_terms.size(), 1u);
  EXPECT_EQ(back.extension->mean_terms[0].term.knots, drift.knots);
  EXPECT_EQ(back.extension->mean_terms[0].coefficients, c.extension->mean_terms[0].coefficients);
  const std::string knots = "[0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5]";
  ASSERT_NE(good.find("knots: " + knots), std::string::npos) << good;
  std::string eighteen = "[0";
  for (int i = 1; i < 18; ++i) eighteen += ", " + std::to_string(i);
  const std::string refused = error_of(replaced(good, knots, eighteen + "]"));
  EXPECT_NE(refused.find("extension.terms[0]"), std::string::npos) << refused;
  EXPECT_NE(refused.find("needs 3 to 17 knots, has 18"), std::string::npos) << refused;
}

TEST(CalibrationFile, ExtensionErrorsNameTheKey) {
  core::Calibration c = example();
  c.extension = core::ModelExtension{};
  core::Term decay =
      term(core::Parameter::Bias, core::Covariate::TimeSincePowerOn, core::Form::Decay);
  decay.time_constant_s = 240.0;
  c.extension->effects = {decay.label(), {core::Parameter::Markov, core::Covariate::None}};
  c.extension->mean_terms = {{decay, Eigen::VectorXd::Constant(1, 1.5)}};
  c.extension->extended_mixture = core::without_extensions(c.model.mixture);
  c.extension->extended_mixture.transition =
      (Eigen::Matrix2d() << 0.875, 0.125, 0.25, 0.75).finished();
  const std::string good = calibration_to_yaml(c);
  const std::string bad_parameter =
      error_of(replaced(good, "parameter: markov", "parameter: gremlins"));
  EXPECT_NE(bad_parameter.find("'gremlins' is not a parameter of Eq. 8"), std::string::npos)
      << bad_parameter;
  EXPECT_NE(bad_parameter.find("extension.effects[1]"), std::string::npos) << bad_parameter;
  EXPECT_NE(error_of(replaced(good, "[0.875, 0.125]", "[0.875, 0.5]")).find("transition"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, "[0.875, 0.125]", "[0.875]"))
                .find("extension.transition[1] must be a list of numbers as long as the first row"),
            std::string::npos)
      << error_of(replaced(good, "[0.875, 0.125]", "[0.875]"));
  EXPECT_NE(error_of(replaced(good, "covariate: time_since_power_on\n      form",
                              "covariate: moon_phase\n      form"))
                .find("'moon_phase' is not a covariate"),
            std::string::npos)
      << error_of(replaced(good, "covariate: time_since_power_on\n      form",
                           "covariate: moon_phase\n      form"));
  EXPECT_NE(
      error_of(replaced(good, "coefficients_mm", "coefficients_inch")).find("coefficients_inch"),
      std::string::npos);
  // A decay needs its time constant.
  EXPECT_NE(error_of(replaced(good, "      time_constant_s: 240\n", ""))
                .find("needs a positive time constant"),
            std::string::npos)
      << error_of(replaced(good, "      time_constant_s: 240\n", ""));
}

TEST(AtomicFile, ReplacesWholeAndLeavesNoTemporary) {
  const std::string dir = ::testing::TempDir() + "/atomic";
  std::filesystem::create_directories(dir);
  const std::string file = dir + "/target.txt";
  write_file_atomically(file, "old");
  write_file_atomically(file, "new contents");
  EXPECT_EQ(testing::file_text(file), "new contents");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
  EXPECT_THROW(write_file_atomically(dir + "/missing/x.txt", "x"), core::Error);
}

}  // namespace
}  // namespace tofcomp::io
