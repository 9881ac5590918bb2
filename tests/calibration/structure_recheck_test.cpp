// The structure re-checked after the model search kept a term on the bias
// (calibration/structure_recheck.hpp), on twin data whose answer is known from the same record
// without the effect: what §7 chooses there is what the re-check must choose once the kept term's
// bias is taken out.
#include "calibration/structure_recheck.hpp"

#include <gtest/gtest.h>

#include <string>

#include "calibration/junction_recheck.hpp"
#include "calibration/trained_search.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

constexpr std::uint64_t kSeed = 1;
// A drift strong enough that training, choosing the structure with it in the ranges, takes a
// different one: the drift spreads the residuals, and more modes take that in.
constexpr double kDriftMmPerHour = 3.0;

MeasuredData record_with_or_without_drift(bool drift) {
  sim::Scenario scenario =
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/default.yaml");
  scenario.seed = kSeed;
  if (drift) scenario.effects.time_drift = sim::TimeDrift{kDriftMmPerHour};
  return test::twin_measured_data(scenario);
}

std::string chosen_structure(const Training& t) {
  return t.structure->candidates.at(static_cast<std::size_t>(t.structure->chosen)).name;
}

// The whole search, then the re-checks.
TrainedSearch searched_then_rechecked(const MeasuredData& data, const Training& training,
                                      const TrainSettings& settings,
                                      const ModelSearchOptions& options) {
  TrainedSearch out;
  out.training = training;
  out.search = search_model(data, out.training.calibration, out.training.junction, options);
  out = recheck_junction(data, settings, options, std::move(out));
  return recheck_structure(data, settings, options, std::move(out));
}

TEST(StructureRecheck, ChoosesWhatTheRecordWithoutTheEffectChooses) {
  // The command line's defaults: the LMS 200 datasheet as the thermal fit's prior, everything
  // else chosen from the data.
  TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  settings.threads = 2;
  ModelSearchOptions options;
  options.threads = 2;
  // Without the effect: nothing kept, no re-check, and the structure the re-check must reach.
  const MeasuredData clean_record = record_with_or_without_drift(false);
  const TrainedSearch clean = searched_then_rechecked(
      clean_record, train_calibration(clean_record, settings), settings, options);
  ASSERT_TRUE(clean.training.structure.has_value());
  EXPECT_TRUE(clean.search.kept.empty());
  EXPECT_FALSE(clean.structure_recheck.has_value());
  const int expected_modes = clean.training.structure->modes;
  const std::string clean_structure = chosen_structure(clean.training);

  const MeasuredData drift_record = record_with_or_without_drift(true);
  const Training drift_training = train_calibration(drift_record, settings);
  const TrainedSearch drifting =
      searched_then_rechecked(drift_record, drift_training, settings, options);
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
  EXPECT_FALSE(r.first_search_paused);

  // Through search_and_recheck, which pauses the first search at its first kept term on the
  // bias (training kept the case log's junction here, so the junction's re-check, which needs
  // whole searches, cannot run): the re-check at the pause reaches the modes of the record
  // without the drift too, and the search from there keeps the drift first. (The bias taken out
  // is the drift's as fitted alone, not beside the later steps' terms, so the basis chosen may
  // be another of those the held-out ranges do not tell apart.)
  ASSERT_FALSE(junction_may_be_rechecked(drift_training));
  const TrainedSearch paused = search_and_recheck(drift_record, settings, options, drift_training);
  ASSERT_TRUE(paused.structure_recheck.has_value());
  const StructureRecheck& p = *paused.structure_recheck;
  EXPECT_TRUE(p.error.empty()) << p.error;
  EXPECT_TRUE(p.first_search_paused);
  ASSERT_EQ(p.bias_terms.size(), 1U);
  ASSERT_FALSE(p.kept_first.empty());
  EXPECT_EQ(p.kept_first.back().describe(), p.bias_terms.front().describe());
  EXPECT_LE(p.kept_first.size(), r.kept_first.size());
  EXPECT_EQ(p.again_modes, expected_modes) << p.again << " against " << clean_structure;
  EXPECT_TRUE(p.chosen);
  EXPECT_EQ(chosen_structure(paused.training), p.again);
  ASSERT_FALSE(paused.search.kept.empty());
  EXPECT_EQ(paused.search.kept.front().label(),
            (core::EffectLabel{core::Parameter::Bias, core::Covariate::Time}));
}

}  // namespace
}  // namespace tofcomp::calibration
