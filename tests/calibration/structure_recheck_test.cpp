// The structure re-checked after the model search kept a term on the bias
// (calibration/structure_recheck.hpp), on twin data whose answer is known from the same record
// without the effect: what §7 chooses there is what the re-check must choose once the kept term's
// bias is taken out.
#include "calibration/structure_recheck.hpp"

#include <gtest/gtest.h>

#include <string>

#include "calibration/junction_recheck.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

const std::string kRoot = TOFCOMP_SOURCE_ROOT;
constexpr std::uint64_t kSeed = 1;
// A drift strong enough that training, choosing the structure with it in the ranges, takes a
// different one: the drift spreads the residuals, and more modes take that in.
constexpr double kDriftMmPerHour = 3.0;

MeasuredData twin_record(bool drift) {
  sim::Scenario scenario = sim::load_scenario_file(kRoot + "/config/scenarios/default.yaml");
  scenario.seed = kSeed;
  if (drift) scenario.effects.time_drift = sim::TimeDrift{kDriftMmPerHour};
  return test::twin_measured_data(scenario);
}

std::string chosen_structure(const Training& t) {
  return t.structure->candidates.at(static_cast<std::size_t>(t.structure->chosen)).name;
}

TrainedSearch trained_and_searched(const MeasuredData& data, const TrainSettings& settings,
                                   const ModelSearchOptions& options) {
  TrainedSearch out;
  out.training = train_calibration(data, settings);
  out.search = search_model(data, out.training.calibration, out.training.junction, options);
  out = recheck_junction(data, settings, options, std::move(out));
  return recheck_structure(data, settings, options, std::move(out));
}

TEST(StructureRecheck, ChoosesWhatTheRecordWithoutTheEffectChooses) {
  // The command line's defaults: the LMS 200 datasheet as the thermal fit's prior, everything
  // else chosen from the data.
  TrainSettings settings;
  settings.thermal.datasheet = io::read_datasheet_file(kRoot + "/config/lms200-datasheet.yaml");
  settings.threads = 2;
  ModelSearchOptions options;
  options.threads = 2;
  // Without the effect: nothing kept, no re-check, and the structure the re-check must reach.
  const TrainedSearch clean = trained_and_searched(twin_record(false), settings, options);
  ASSERT_TRUE(clean.training.structure.has_value());
  EXPECT_TRUE(clean.search.kept.empty());
  EXPECT_FALSE(clean.structure_recheck.has_value());
  const int expected_modes = clean.training.structure->modes;
  const std::string clean_structure = chosen_structure(clean.training);

  const TrainedSearch drifting = trained_and_searched(twin_record(true), settings, options);
  ASSERT_TRUE(drifting.structure_recheck.has_value());
  const StructureRecheck& r = *drifting.structure_recheck;
  EXPECT_TRUE(r.error.empty()) << r.error;
  // The drift moved training's choice of modes (else there is nothing to re-check here).
  ASSERT_NE(r.first_modes, expected_modes) << r.first << " against " << clean_structure;
  ASSERT_FALSE(r.bias_terms.empty());
  EXPECT_EQ(r.bias_terms.front().label(),
            (core::EffectLabel{core::Parameter::Bias, core::Covariate::Time}));
  // Chosen again without the drift's bias: the modes of the record without it. (The basis may
  // differ among those the held-out ranges do not tell apart.)
  EXPECT_EQ(r.again_modes, expected_modes) << r.again << " against " << clean_structure;
  EXPECT_TRUE(r.searched_again);
  EXPECT_TRUE(r.chosen);
  // The result reported is the re-check's: trained at that structure, the drift kept from it.
  ASSERT_TRUE(drifting.training.structure.has_value());
  EXPECT_EQ(chosen_structure(drifting.training), r.again);
  ASSERT_FALSE(drifting.search.kept.empty());
  EXPECT_EQ(drifting.search.kept.front().label(),
            (core::EffectLabel{core::Parameter::Bias, core::Covariate::Time}));
}

}  // namespace
}  // namespace tofcomp::calibration
