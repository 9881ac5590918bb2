// The junction re-checked from the ranges' untested answer (calibration/junction_recheck.hpp), on
// the twin's warm-up (3 mm decaying in 300 s after each power-on) with the datasheet's junction,
// whose answer is known: training keeps the case log's junction (the ranges' blocks do not reject
// it), the search keeps a term, so the re-check trains again with the ranges' answer, reports
// both starts, and keeps the one whose final model has the larger held-out log-likelihood per
// range; the search reported is that start's, and the warm-up, which the twin put there, is kept
// first from either. Training asked for the ranges' answer takes it untested and says so.
#include "calibration/junction_recheck.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "calibration/trained_search.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

TrainSettings command_line_defaults() {
  TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  settings.threads = 2;
  return settings;
}

std::vector<core::EffectLabel> labels(const std::vector<core::Term>& terms) {
  std::vector<core::EffectLabel> out;
  for (const core::Term& t : terms) out.push_back(t.label());
  return out;
}

MeasuredData warm_up_record() {
  return test::twin_measured_data(
      sim::load_scenario_file(testing::kSourceRoot + "/config/scenarios/effect-warm-up.yaml"));
}

TEST(JunctionRecheck, TheRangesUntestedAnswerIsJudgedOnHeldOutRanges) {
  const TrainSettings settings = command_line_defaults();
  ModelSearchOptions options;
  options.threads = 2;
  const MeasuredData data = warm_up_record();
  TrainedSearch first;
  first.training = train_calibration(data, settings);
  ASSERT_TRUE(first.training.junction_dynamics.has_value());
  const JunctionDynamicsFit& fit = *first.training.junction_dynamics;
  ASSERT_FALSE(fit.replaced) << "the ranges rejected the datasheet's junction: t " << fit.block_t;
  ASSERT_TRUE(fit.ranges_answer_above_start());
  ASSERT_EQ(junction_alternative(first.training), JunctionSource::Ranges);
  first.search = search_model(data, first.training.calibration, first.training.junction, options);
  ASSERT_FALSE(first.search.kept.empty());
  const std::vector<core::Term> kept_first = first.search.kept;

  const TrainedSearch rechecked = recheck_junction(data, settings, options, first);
  ASSERT_TRUE(rechecked.junction_recheck.has_value());
  const JunctionRecheck& r = *rechecked.junction_recheck;
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.first_from_ranges);
  EXPECT_EQ(labels(r.kept_from_case_log), labels(kept_first));
  EXPECT_EQ(r.from_case_log.rise_k, fit.start.dynamics.rise_k);
  EXPECT_EQ(r.from_ranges.time_constant_s, fit.best.dynamics.time_constant_s);
  EXPECT_GT(r.common_ranges, 0);
  EXPECT_EQ(r.case_log_chosen, r.from_case_log_per_range() >= r.from_ranges_per_range());
  // The start reported is the chosen one: its junction and what its search kept.
  const JunctionDynamicsFit& reported = *rechecked.training.junction_dynamics;
  EXPECT_EQ(reported.replaced_untested, !r.case_log_chosen);
  EXPECT_EQ(labels(rechecked.search.kept),
            labels(r.case_log_chosen ? r.kept_from_case_log : r.kept_from_ranges));
  const JunctionDynamics carried = junction_dynamics_of(rechecked.training.calibration.thermal);
  const JunctionDynamics& chosen = r.case_log_chosen ? r.from_case_log : r.from_ranges;
  EXPECT_NEAR(carried.rise_k / chosen.rise_k, 1.0, 1e-9);
  EXPECT_NEAR(carried.time_constant_s / chosen.time_constant_s, 1.0, 1e-9);
  // The twin's warm-up is real: the search from either junction keeps it first.
  for (const std::vector<core::Term>* kept : {&r.kept_from_case_log, &r.kept_from_ranges}) {
    ASSERT_FALSE(kept->empty());
    EXPECT_EQ(kept->front().label(),
              (core::EffectLabel{core::Parameter::Bias, core::Covariate::TimeSincePowerOn}));
  }
  // Asked for again with the chosen start's source, training reaches the same junction.
  const TrainSettings again = with_rechecked_junction(settings, rechecked.junction_recheck);
  EXPECT_EQ(again.junction_source,
            r.case_log_chosen ? JunctionSource::CaseLog : JunctionSource::Ranges);
}

TEST(JunctionRecheck, TrainingAskedForTheRangesAnswerTakesItUntested) {
  TrainSettings settings = command_line_defaults();
  settings.junction_source = JunctionSource::Ranges;
  const Training t = train_calibration(warm_up_record(), settings);
  ASSERT_TRUE(t.junction_dynamics.has_value());
  const JunctionDynamicsFit& fit = *t.junction_dynamics;
  EXPECT_TRUE(fit.replaced);
  EXPECT_EQ(fit.replaced_untested, fit.block_p >= settings.junction_dynamics.rejection_level);
  const JunctionDynamics carried = junction_dynamics_of(t.calibration.thermal);
  EXPECT_NEAR(carried.rise_k / fit.best.dynamics.rise_k, 1.0, 1e-9);
  EXPECT_NEAR(carried.time_constant_s / fit.best.dynamics.time_constant_s, 1.0, 1e-9);
  // Trained this way there is no untested answer left: the alternative is the case log's.
  EXPECT_EQ(junction_alternative(t), JunctionSource::CaseLog);
}

}  // namespace
}  // namespace tofcomp::calibration
