// The Cramér–Rao bound of d against answers known in closed form: a fine-grained Gaussian
// (I = 1/σ²), rounding's loss of information, modes far apart (each range's mode is known), and
// the bound as a mean absolute error.
#include "core/cramer_rao.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

MixtureParameters modes(std::initializer_list<double> mean, std::initializer_list<double> std_mm,
                        std::initializer_list<double> weight) {
  MixtureParameters m;
  m.mean = Eigen::Map<const Eigen::VectorXd>(mean.begin(), static_cast<Eigen::Index>(mean.size()));
  m.variance =
      Eigen::Map<const Eigen::VectorXd>(std_mm.begin(), static_cast<Eigen::Index>(std_mm.size()))
          .array()
          .square();
  m.weight =
      Eigen::Map<const Eigen::VectorXd>(weight.begin(), static_cast<Eigen::Index>(weight.size()));
  return m;
}

TEST(CramerRao, AFinelyResolvedGaussianHoldsOneOverSigmaSquared) {
  EXPECT_NEAR(range_fisher_information(modes({0.0}, {3.0}, {1.0}), 1e-3) * 9.0, 1.0, 1e-4);
}

// Rounding to 1 mm costs information, about as adding its variance 1/12 mm² would (Sheppard).
TEST(CramerRao, RoundingToMillimetresCostsAboutATwelfth) {
  const double i = range_fisher_information(modes({0.0}, {2.0}, {1.0}), 1.0);
  EXPECT_LT(i, 1.0 / 4.0);
  EXPECT_NEAR(i * (4.0 + 1.0 / 12.0), 1.0, 0.01);
}

// Modes 40 σ apart: every range's mode is known, so the mixture informs as one Gaussian does;
// two modes at one offset are one mode.
TEST(CramerRao, ModesFarApartOrTogetherInformAsOneGaussian) {
  EXPECT_NEAR(range_fisher_information(modes({-20.0, 20.0}, {1.0, 1.0}, {0.5, 0.5}), 1e-3), 1.0,
              1e-4);
  EXPECT_NEAR(range_fisher_information(modes({1.0, 1.0}, {2.0, 2.0}, {0.3, 0.7}), 0.5),
              range_fisher_information(modes({1.0}, {2.0}, {1.0}), 0.5), 1e-12);
  // Overlapping modes hold less than their narrowest alone would.
  EXPECT_LT(range_fisher_information(modes({0.0, 3.0}, {1.0, 1.0}, {0.5, 0.5}), 1e-3), 1.0);
}

TEST(CramerRao, TheBoundAsAMeanAbsoluteError) {
  // σ = 3 mm, n = 100: the standard error is 0.3 mm, its mean absolute value √(2/π) · 0.3.
  EXPECT_NEAR(cramer_rao_mae_mm(range_fisher_information(modes({0.0}, {3.0}, {1.0}), 1e-3), 100),
              std::sqrt(2.0 / std::numbers::pi) * 0.3, 1e-4);
  EXPECT_THROW(cramer_rao_mae_mm(1.0 / 9.0, 0), InvalidInput);
  EXPECT_THROW(cramer_rao_mae_mm(0.0, 100), InvalidInput);
  EXPECT_THROW(range_fisher_information(modes({0.0}, {3.0}, {1.0}), 0.0), InvalidInput);
}

// The generator of ../shared/data/foreign, written apart from this project, states in each truth
// file the bound for its modes and 1 mm rounding (crb_mae_mm): the same numbers, to 0.5 %.
TEST(CramerRao, AgreesWithTheForeignTruthFiles) {
  const std::filesystem::path dir =
      std::filesystem::path(TOFCOMP_SOURCE_ROOT) / ".." / "shared" / "data" / "foreign";
  int checked = 0;
  for (int set = 1; set <= 8; ++set) {
    const auto file = dir / ("foreign-" + std::to_string(set) + ".truth.json");
    std::ifstream in(file);
    ASSERT_TRUE(in) << "missing " << file;
    const nlohmann::json truth = nlohmann::json::parse(in);
    const auto& m = truth.at("modes");
    MixtureParameters mixture;
    const auto count = static_cast<Eigen::Index>(m.at("offset_mm").size());
    mixture.mean.resize(count);
    mixture.variance.resize(count);
    mixture.weight.resize(count);
    for (Eigen::Index i = 0; i < count; ++i) {
      const auto j = static_cast<std::size_t>(i);
      mixture.mean[i] = m.at("offset_mm")[j].get<double>();
      mixture.variance[i] = std::pow(m.at("std_mm")[j].get<double>(), 2);
      mixture.weight[i] = m.at("weight")[j].get<double>();
    }
    mixture.weight /= mixture.weight.sum();
    const double information = range_fisher_information(mixture, 1.0);
    for (const int n : {200, 400, 800}) {
      const double stated = truth.at("crb_mae_mm").at(std::to_string(n)).get<double>();
      EXPECT_NEAR(cramer_rao_mae_mm(information, n) / stated, 1.0, 0.005) << file << " n " << n;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 24);
}

}  // namespace
}  // namespace tofcomp::core
