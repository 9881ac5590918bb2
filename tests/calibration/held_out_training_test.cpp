// tofcompd's recalibration as the training child runs it (calibration/held_out_training.hpp) on
// twin data whose truth is known by construction: with the model search on, a record with a
// time drift the paper's model lacks gets a calibration that carries the drift term, and on the
// held-out part it estimates d better than the running calibration (the shipped one, trained on
// the default scenario, which has no drift); on a record without an effect the search keeps
// nothing; with the search off the calibration is the paper's model.
#include "calibration/held_out_training.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "calibration/measured_data_reader.hpp"
#include "io/calibration_file.hpp"
#include "io/datasheet_file.hpp"
#include "sim/scenario_yaml.hpp"
#include "tests/support/source_root.hpp"
#include "tests/support/twin_measured_data.hpp"

namespace tofcomp::calibration {
namespace {

MeasuredData scenario_record(const std::string& scenario_name) {
  return test::twin_measured_data(sim::load_scenario_file(
      testing::kSourceRoot + "/config/scenarios/" + scenario_name + ".yaml"));
}

// The daemon's settings: the defaults, and the datasheet it is configured with.
TrainSettings daemon_settings() {
  TrainSettings settings;
  settings.thermal.datasheet =
      io::read_datasheet_file(testing::kSourceRoot + "/config/lms200-datasheet.yaml");
  return settings;
}

core::Calibration shipped_calibration() {
  return io::read_calibration_file(testing::kSourceRoot + "/config/calibration.yaml");
}

TEST(HeldOutTrainingWithSearch, CarriesTheTimeDriftAndBeatsTheRunningCalibration) {
  const MeasuredData data = scenario_record("effect-time-drift");
  const core::Calibration running = shipped_calibration();
  const ModelSearchOptions search;
  const HeldOutTraining trained = train_with_held_out(data, daemon_settings(), &running, &search);
  std::printf("%s\n", trained.note.c_str());
  ASSERT_TRUE(trained.training.calibration.extension.has_value()) << trained.note;
  const core::EffectLabel drift{core::Parameter::Bias, core::Covariate::Time};
  EXPECT_EQ(trained.training.calibration.extension->effects.front(), drift) << trained.note;
  ASSERT_FALSE(trained.kept_terms.empty());
  EXPECT_EQ(trained.kept_terms.front(), core::effect_name(drift));
  EXPECT_NE(trained.note.find("the model search kept " + core::effect_name(drift)),
            std::string::npos)
      << trained.note;
  ASSERT_TRUE(trained.comparison.has_value()) << trained.note;
  std::printf("held-out d̂ MAE %.3f mm, running calibration %.3f mm\n",
              trained.comparison->new_mae_mm, trained.comparison->running_mae_mm);
  EXPECT_LT(trained.comparison->new_mae_mm, trained.comparison->running_mae_mm);
  // The extended calibration passes the daemon's gate.
  EXPECT_TRUE(implausibilities(trained.training.calibration).empty());
  EXPECT_FALSE(held_out_regression(*trained.comparison).has_value());
}

TEST(HeldOutTrainingWithSearch, KeepsNothingWithoutAnEffect) {
  const MeasuredData data = scenario_record("default");
  const core::Calibration running = shipped_calibration();
  const ModelSearchOptions search;
  const HeldOutTraining trained = train_with_held_out(data, daemon_settings(), &running, &search);
  std::printf("%s\n", trained.note.c_str());
  EXPECT_FALSE(trained.training.calibration.extension.has_value()) << trained.note;
  EXPECT_TRUE(trained.kept_terms.empty());
  EXPECT_NE(trained.note.find("the model search kept no term"), std::string::npos) << trained.note;
}

TEST(HeldOutTrainingWithSearch, WithoutTheSearchTrainsThePapersModel) {
  const MeasuredData data = scenario_record("effect-time-drift");
  const core::Calibration running = shipped_calibration();
  const HeldOutTraining trained = train_with_held_out(data, daemon_settings(), &running);
  EXPECT_FALSE(trained.training.calibration.extension.has_value());
  EXPECT_TRUE(trained.kept_terms.empty());
  EXPECT_EQ(trained.note.find("model search"), std::string::npos) << trained.note;
}

}  // namespace
}  // namespace tofcomp::calibration
