// Training's final fit when EM empties a mode the structure search counted
// (calibration/final_fit.hpp): the mode is dropped and the fit goes on with the modes the data
// show, where core::train_em alone refuses the data.
#include "calibration/final_fit.hpp"

#include <gtest/gtest.h>

#include <random>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

constexpr double kFirstOffsetMm = 0.0;
constexpr double kSecondOffsetMm = 4.5;
constexpr double kModeStdMm = 0.6;

struct Record {
  Eigen::MatrixXd h;
  Eigen::VectorXd y;
};

// y − d = θ x + a two-mode mixture (weights 0.6 and 0.4), x a ramp over [−1, 1] (H has no
// constant column: the modes' offsets carry it, Eq. 8).
Record two_mode_record() {
  const Eigen::Index k = 4000;
  Record r{Eigen::MatrixXd(k, 1), Eigen::VectorXd(k)};
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, kModeStdMm);
  std::bernoulli_distribution second(0.4);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double x = -1.0 + 2.0 * static_cast<double>(i) / static_cast<double>(k - 1);
    r.h(i, 0) = x;
    r.y[i] = 2.0 * x + (second(rng) ? kSecondOffsetMm : kFirstOffsetMm) + noise(rng);
  }
  return r;
}

// Three modes, the third 40 mm away from every range with 1 % of the weight: EM empties it at
// its first step.
core::EmTrainOptions three_modes_one_of_them_empty() {
  core::EmTrainOptions o;
  o.modes = 3;
  core::MixtureParameters m{Eigen::Vector3d(kFirstOffsetMm, kSecondOffsetMm, 40.0),
                            Eigen::Vector3d::Constant(kModeStdMm * kModeStdMm),
                            Eigen::Vector3d(0.59, 0.40, 0.01)};
  o.start = core::EmStartingPoint{Eigen::VectorXd::Constant(1, 2.0), m};
  return o;
}

TEST(FinalFit, EmAloneRefusesTheDataNamingTheEmptiedMode) {
  const Record r = two_mode_record();
  try {
    core::train_em(r.h, r.y, three_modes_one_of_them_empty());
    FAIL() << "EM kept a mode no range is near";
  } catch (const core::EmptiedModeError& e) {
    EXPECT_EQ(e.mode(), 2);
  }
}

TEST(FinalFit, AnEmptiedModeIsDroppedAndTheModesTheDataShowAreFitted) {
  const Record r = two_mode_record();
  const FinalFit fit = train_em_dropping_emptied_modes(r.h, r.y, three_modes_one_of_them_empty());
  ASSERT_EQ(fit.dropped_modes.size(), 1u);
  EXPECT_NE(fit.dropped_modes[0].find("mode 3 of 3"), std::string::npos) << fit.dropped_modes[0];
  ASSERT_EQ(fit.em.mixture.modes(), 2);
  EXPECT_NEAR(fit.em.mixture.mean[0], kFirstOffsetMm, 0.1);
  EXPECT_NEAR(fit.em.mixture.mean[1], kSecondOffsetMm, 0.1);
  EXPECT_NEAR(fit.em.mixture.weight[1], 0.4, 0.03);
  EXPECT_NEAR(fit.em.theta[0], 2.0, 0.1);
  EXPECT_TRUE(fit.em.converged);
}

TEST(FinalFit, AFitThatKeepsItsModesIsCoreEmUnchanged) {
  const Record r = two_mode_record();
  core::EmTrainOptions o;
  o.modes = 2;
  const FinalFit fit = train_em_dropping_emptied_modes(r.h, r.y, o);
  const core::EmTrainResult alone = core::train_em(r.h, r.y, o);
  EXPECT_TRUE(fit.dropped_modes.empty());
  EXPECT_EQ(fit.em.log_likelihood, alone.log_likelihood);
  EXPECT_EQ(fit.em.iterations, alone.iterations);
}

}  // namespace
}  // namespace tofcomp::calibration
