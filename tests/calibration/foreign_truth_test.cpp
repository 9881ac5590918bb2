// The foreign data (../shared/data/foreign: drawn by a generator written apart from this
// project, each set with a truth file) calibrated with training's defaults, as `tofcomp evaluate`
// does (the first half trained on, the rest tested), and checked against the truth:
//   - the thermal combinations a case log determines (core/thermal_identification.hpp): the
//     case's steady gain P·R2 within 5 % and its time constant R2·C2 within 10 %;
//   - where the ranges replaced the case-log fit's junction (calibration/junction_dynamics.hpp),
//     the junction's time constant R1·C1 moved towards the truth: nearer to it, in logarithm,
//     than the case-log fit's;
//   - the lasing modes as a distribution: the trained mixture's CDF, centred, within 0.02 of the
//     truth's (its spreads widened by the 1 mm rounding's h²/12) everywhere, whether or not the
//     search split or merged a mode;
//   - the Cramér–Rao bound `evaluate` prints, from the trained modes, within 3 % of the truth
//     file's (from the true modes): the trained spreads hold the rounding's variance, and a bound
//     that rounded them again was 1-8 % too lenient;
//   - the window estimate d̂ on the test half's windows inside the junction temperatures trained
//     on: its mean absolute error at most 1.25 × the truth file's Cramér–Rao bound (beyond them
//     the bias is extrapolated, and the bound is out of reach: docs/performance.md).
// The truth is read here only; nothing of it reaches training.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "calibration/compensation.hpp"
#include "calibration/measured_data_reader.hpp"
#include "calibration/training.hpp"
#include "calibration/window_evaluation.hpp"
#include "io/datasheet_file.hpp"
#include "tests/support/source_root.hpp"

namespace tofcomp::calibration {
namespace {

constexpr double kSteadyGainTolerance = 0.05;
constexpr double kCaseTimeConstantTolerance = 0.10;
constexpr double kMixtureCdfTolerance = 0.02;
constexpr double kEfficiencyGoal = 1.25;  // MAE of d̂ / Cramér–Rao bound (issue 13)
constexpr double kBoundTolerance = 0.03;  // the printed bound against the truth file's
// Every 10th window: the error moments over tens of thousands of windows do not need all.
constexpr Eigen::Index kWindowStride = 10;

const std::filesystem::path kForeign =
    std::filesystem::path(testing::kSourceRoot) / ".." / "shared" / "data" / "foreign";

struct Mode {
  double offset_mm, std_mm, weight;
};

double centred_cdf(double x, const std::vector<Mode>& modes) {
  double mean = 0.0;
  for (const Mode& m : modes) mean += m.weight * m.offset_mm;
  double cdf = 0.0;
  for (const Mode& m : modes) {
    cdf += m.weight * 0.5 * std::erfc(-(x + mean - m.offset_mm) / (m.std_mm * std::sqrt(2.0)));
  }
  return cdf;
}

class ForeignTruth : public ::testing::TestWithParam<int> {};

TEST_P(ForeignTruth, CalibratedWithTheDefaultsWithinTheTruthsTolerances) {
  const std::string name = "foreign-" + std::to_string(GetParam());
  std::ifstream truth_file(kForeign / (name + ".truth.json"));
  ASSERT_TRUE(truth_file) << "missing " << (kForeign / (name + ".truth.json"));
  const nlohmann::json truth = nlohmann::json::parse(truth_file);
  std::vector<std::string> warnings;
  const MeasuredData all = read_measured_data((kForeign / (name + ".csv")).string(), 0, warnings);
  const double split = split_time(all, 0.5);
  const MeasuredData train = all.slice(-1e300, split);
  const MeasuredData test = all.slice(split, 1e300);

  TrainSettings settings;  // tofcomp's defaults: the bundled LMS 200 datasheet is this file
  settings.thermal.datasheet = io::read_datasheet_file(std::filesystem::path(testing::kSourceRoot) /
                                                       "config" / "lms200-datasheet.yaml");
  const Training t = train_calibration(train, settings, &test);

  const core::ThermalParameters& fitted = t.calibration.thermal;
  const nlohmann::json& thermal = truth["thermal"];
  const double true_gain = thermal["P"].get<double>() * thermal["R2"].get<double>();
  const double true_tau = thermal["R2"].get<double>() * thermal["C2"].get<double>();
  EXPECT_NEAR(fitted.power_w * fitted.r2_k_per_w / true_gain, 1.0, kSteadyGainTolerance) << name;
  EXPECT_NEAR(fitted.r2_k_per_w * fitted.c2_j_per_k / true_tau, 1.0, kCaseTimeConstantTolerance)
      << name;
  ASSERT_TRUE(t.junction_dynamics.has_value()) << name;
  if (t.junction_dynamics->replaced) {
    const double true_junction_tau = thermal["R1"].get<double>() * thermal["C1"].get<double>();
    const auto log_distance = [&](double tau) {
      return std::abs(std::log(tau / true_junction_tau));
    };
    EXPECT_LT(log_distance(t.junction_dynamics->best.dynamics.time_constant_s),
              log_distance(t.junction_dynamics->start.dynamics.time_constant_s))
        << name << ": R1·C1 " << t.junction_dynamics->best.dynamics.time_constant_s
        << " s from the ranges, " << t.junction_dynamics->start.dynamics.time_constant_s
        << " s from the case log, " << true_junction_tau << " s true";
  }

  std::vector<Mode> true_modes, trained_modes;
  const nlohmann::json& modes = truth["modes"];
  for (std::size_t i = 0; i < modes["weight"].size(); ++i) {
    const double std_mm = modes["std_mm"][i].get<double>();
    true_modes.push_back(
        {modes["offset_mm"][i].get<double>(),
         std::sqrt(std_mm * std_mm + kRangeResolutionMm * kRangeResolutionMm / 12.0),
         modes["weight"][i].get<double>()});
  }
  const core::MixtureParameters& mixture = t.calibration.model.mixture;
  for (int i = 0; i < mixture.modes(); ++i) {
    trained_modes.push_back({mixture.mean[i], std::sqrt(mixture.variance[i]), mixture.weight[i]});
  }
  for (double x = -20.0; x <= 20.0; x += 0.1) {
    ASSERT_NEAR(centred_cdf(x, trained_modes), centred_cdf(x, true_modes), kMixtureCdfTolerance)
        << name << " at " << x << " mm from the mixture's mean; " << mixture.modes()
        << " modes trained, " << true_modes.size() << " true";
  }

  const Compensation compensation = compensate(test, t.calibration);
  const auto evaluations =
      evaluate_windows(test, t.calibration, compensation, {200, 400, 800}, kWindowStride);
  for (const WindowEvaluation& e : evaluations) {
    const double bound = truth["crb_mae_mm"][std::to_string(e.window)].get<double>();
    EXPECT_NEAR(e.cramer_rao_mae_mm / bound, 1.0, kBoundTolerance)
        << name << " window " << e.window << ": the bound from the trained modes "
        << e.cramer_rao_mae_mm << " mm, the truth's " << bound << " mm";
    ASSERT_GT(e.em_inside_trained.count, 0) << name;
    EXPECT_LE(e.em_inside_trained.mean_absolute_error / bound, kEfficiencyGoal)
        << name << " window " << e.window << " (all windows: " << e.em.mean_absolute_error / bound
        << " × the bound)";
  }
}

INSTANTIATE_TEST_SUITE_P(Sets, ForeignTruth, ::testing::Range(1, 9));

}  // namespace
}  // namespace tofcomp::calibration
