// The daemon's compensation path (realtime/, as `tofcomp replay` runs it) with a calibration
// that carries what the model search kept, on twin data with an effect: the search on the first
// part (calibration::search_model) keeps the term of that effect, and its calibration makes the
// real-time window estimates d̂ (the daemon's default incremental window of 200) closer to the
// true distance on the held-out part than the paper's model alone: the ratio of mean absolute
// errors, paper's over extended, exceeds a per-effect bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <tuple>

#include "calibration/measured_data_reader.hpp"
#include "calibration/model_search.hpp"
#include "calibration/training.hpp"
#include "io/datasheet_file.hpp"
#include "realtime/recording_replay.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

// The twin's events as a tofcompd recording of one beam: power changes and case readings
// before a range at the same time, as the daemon takes them.
// The record as tofcompd would have recorded it (one beam), with the data's logged ambient rows
// where `with_ambient` (a recording from another logger; tofcompd's own log none).
io::MeasurementTable recording_of(const MeasuredData& data, bool with_ambient = false) {
  io::MeasurementTable table;
  table.metadata = io::recording_metadata(1, 0.0, 1.0);
  table.columns = io::recording_columns();
  std::vector<std::tuple<double, int, io::MeasurementRow>> events;
  for (const auto& [time_s, on] : data.power_changes) {
    io::MeasurementRow row;
    row.time_s = time_s;
    row.power = on;
    events.emplace_back(time_s, 0, row);
  }
  for (Eigen::Index k = 0; k < data.case_c.size(); ++k) {
    io::MeasurementRow row;
    row.time_s = data.temperature_time_s[k];
    row.case_temp_c = data.case_c[k];
    events.emplace_back(row.time_s, 1, row);
  }
  if (with_ambient) {
    for (const auto& [time_s, ambient_c] : data.ambient) {
      io::MeasurementRow row;
      row.time_s = time_s;
      row.ambient_c = ambient_c;
      events.emplace_back(time_s, 1, row);
    }
  }
  for (Eigen::Index k = 0; k < data.range_mm.size(); ++k) {
    io::MeasurementRow row;
    row.time_s = data.range_time_s[k];
    row.range_mm = data.range_mm[k];
    row.beam = 0;
    events.emplace_back(row.time_s, 2, row);
  }
  std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  for (auto& e : events) table.rows.push_back(std::move(std::get<2>(e)));
  return table;
}

// Mean |d̂ − d| of the published window estimates from `from_s` on (windows still filling
// excluded).
double window_error(const core::Calibration& calibration, const io::MeasurementTable& recording,
                    const MeasuredData& data, double from_s, std::string* flags_seen) {
  realtime::CompensationPipeline pipeline;
  pipeline.set_calibration(std::make_shared<const core::Calibration>(calibration), 1);
  double sum = 0.0;
  long count = 0;
  Eigen::Index k = 0;
  long outliers = 0;
  realtime::replay_recording(recording, "twin", pipeline, [&](const ipc::CompensatedScan& s) {
    const double time_s = data.range_time_s[k];
    const double truth = data.true_range_mm[k];
    ++k;
    const ipc::BeamValue& v = s.beams[0];
    if (v.flags & ipc::kBeamOutlier) ++outliers;
    if (time_s < from_s || !std::isfinite(v.window_mm)) return;
    sum += std::abs(v.window_mm - truth);
    ++count;
  });
  EXPECT_EQ(k, data.range_mm.size());
  if (flags_seen) *flags_seen = "outlier flags " + std::to_string(outliers);
  EXPECT_GT(count, data.range_mm.size() / 3);
  return sum / static_cast<double>(count);
}

struct ExtensionCase {
  const char* scenario;
  core::EffectLabel label;  // what the search keeps first
  double min_ratio;         // MAE of the paper's model over MAE with the extension
};

class ReplayWithExtension : public ::testing::TestWithParam<ExtensionCase> {};

TEST_P(ReplayWithExtension, EstimatesCloserToTheTruth) {
  const ExtensionCase& c = GetParam();
  sim::Scenario scenario =
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/" + c.scenario + ".yaml");
  scenario.seed = 11;
  const MeasuredData data = test::twin_measured_data(scenario);
  TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  // Eq. 8 as printed, as the diagnosis tests judge the extensions (diagnose_test.cpp).
  settings.basis = "polynomial:4";
  settings.modes = 2;
  settings.kalman_noise = core::ThermalNoise{};
  const double split = split_time(data, 0.5);
  const MeasuredData first = data.slice(-1e300, split);
  const Training trained = train_calibration(first, settings);
  const ModelSearchResult search = search_model(first, trained.calibration, trained.junction);
  ASSERT_TRUE(search.calibration.extension.has_value()) << c.scenario;
  ASSERT_EQ(search.calibration.extension->effects.front(), c.label)
      << c.scenario << ": kept " << search.calibration.extension->name();
  const core::Calibration& extended = search.calibration;
  const core::Calibration& base = trained.calibration;

  const io::MeasurementTable recording = recording_of(data);
  std::string flags_base, flags_extended;
  const double before = window_error(base, recording, data, split, &flags_base);
  const double after = window_error(extended, recording, data, split, &flags_extended);
  std::printf(
      "%s: window MAE %.4f mm with the paper's model, %.4f mm with the extension "
      "(ratio %.2f; %s)\n",
      c.scenario, before, after, before / after, flags_extended.c_str());
  EXPECT_GT(before / after, c.min_ratio) << c.scenario;
}

// The ratios measured (seed 11) are in docs/closing-the-loop.md; each bound is a margin below.
INSTANTIATE_TEST_SUITE_P(
    Effects, ReplayWithExtension,
    ::testing::Values(
        ExtensionCase{"effect-outliers", {core::Parameter::Outliers, core::Covariate::None}, 2.0},
        ExtensionCase{"effect-time-drift", {core::Parameter::Bias, core::Covariate::Time}, 10.0},
        ExtensionCase{
            "effect-warm-up", {core::Parameter::Bias, core::Covariate::TimeSincePowerOn}, 1.8},
        ExtensionCase{
            "effect-mode-persistence", {core::Parameter::Markov, core::Covariate::None}, 1.1}));

// The twin in a 28 °C room (seed 11), trained on its first half as `tofcomp train` trains (the
// filter's noise levels fitted to the case log: the smaller they are, the more the filter's
// junction follows the model at its ambient).
struct WarmRoom {
  static constexpr double kRoomC = 28.0;
  MeasuredData data;
  double split = 0.0;
  Training trained;
  core::Calibration at_fallback;  // the trained calibration at the 22 °C fallback's ambient
  double fallback_c = 0.0;

  WarmRoom() {
    sim::Scenario scenario =
        sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/default.yaml");
    scenario.seed = 11;
    scenario.ambient.base_c = kRoomC;
    data = test::twin_measured_data(scenario);
    TrainSettings settings;
    settings.thermal.datasheet =
        io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
    settings.basis = "polynomial:4";
    settings.modes = 2;
    split = split_time(data, 0.5);
    trained = train_calibration(data.slice(-1e300, split), settings);
    fallback_c = settings.thermal.ambient_fallback_c;
    at_fallback = trained.calibration;
    at_fallback.ambient_c = fallback_c;
  }
};

// A calibration trained on data logged in a warm room carries that room's ambient (the median
// the data logged at their ranges), so the daemon's path, which has no ambient sensor, runs its
// junction filter at it: trained at the fallback of 22 °C instead, the filter's junction stands
// R1 / R2 × 6 K off and d̂ with it (window MAE 0.055 mm against 0.435 mm when written).
TEST(ReplayAtTheLoggedAmbient, TheCalibrationCarriesTheAmbientItsDataLogged) {
  const WarmRoom room;
  ASSERT_FALSE(room.data.ambient.empty());
  EXPECT_NEAR(room.trained.calibration.ambient_c, WarmRoom::kRoomC, 0.1);
  const io::MeasurementTable recording = recording_of(room.data);
  const double logged =
      window_error(room.trained.calibration, recording, room.data, room.split, nullptr);
  const double fallback = window_error(room.at_fallback, recording, room.data, room.split, nullptr);
  std::printf("window MAE %.4f mm at the logged ambient, %.4f mm at the fallback's %.0f °C\n",
              logged, fallback, room.fallback_c);
  EXPECT_LT(logged, 0.5 * fallback);
}

// A recording that logs the ambient gives the daemon's path the room itself: the junction filter
// runs at each reading (and an ambient term reads it), so the calibration's ambient no longer
// matters. The calibration's ambient set to the 22 °C fallback: at it the filter's junction
// stands R1 / R2 × 6 K off (the test above); read from the recording, the room is right.
TEST(ReplayAtTheLoggedAmbient, ARecordingThatLogsTheAmbientGivesTheFilterTheRoom) {
  const WarmRoom room;
  const io::MeasurementTable unlogged = recording_of(room.data);
  const io::MeasurementTable logged = recording_of(room.data, true);
  const double calibration_room =
      window_error(room.trained.calibration, unlogged, room.data, room.split, nullptr);
  const double fallback_room =
      window_error(room.at_fallback, unlogged, room.data, room.split, nullptr);
  const double read_room = window_error(room.at_fallback, logged, room.data, room.split, nullptr);
  std::printf(
      "window MAE %.4f mm at the fallback's %.0f °C, %.4f mm at the room read from the "
      "recording, %.4f mm at the calibration's own\n",
      fallback_room, room.fallback_c, read_room, calibration_room);
  EXPECT_LT(read_room, 0.5 * fallback_room);
  EXPECT_NEAR(read_room, calibration_room, 0.2 * calibration_room);
}

}  // namespace
}  // namespace tofcomp::calibration
