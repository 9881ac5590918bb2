#include "core/vector_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "core/basis.hpp"
#include "core/em_train.hpp"
#include "core/gaussian_mixture.hpp"
#include "core/mixture_sweep.hpp"
#include "tests/support/synthetic_measurements.hpp"

namespace tofcomp::core {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Each path is within a few ulp of the exact value (Eigen's ~1 ulp, libmvec's AVX2 kernels
// within 4): the two differ by at most a few ulp per element.
constexpr double kElementRelative = 1e-14;
// Sums over thousands of ranges of such terms, and the E-step's sums of the M-step.
constexpr double kSumRelative = 1e-12;

// Both paths are only comparable where the CPU runs AVX2 and FMA.
class VectorMath : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!vector_math_path_available(VectorMathPath::Avx2Fma)) {
      GTEST_SKIP() << "this build or CPU has no AVX2+FMA path; only the portable one runs";
    }
  }
  void TearDown() override { pin_vector_math_path(std::nullopt); }
};

Eigen::ArrayXd uniform(Eigen::Index n, double lo, double hi, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  Eigen::ArrayXd x(n);
  for (double& v : x) v = u(rng);
  return x;
}

// Three overlapping modes on a cubic bias: y − d and H (a cubic's Legendre basis).
struct MixtureRecord {
  Eigen::VectorXd y;
  Eigen::MatrixXd h;
};
MixtureRecord draw_mixture_record(const MixtureParameters& truth, Eigen::Index ranges,
                                  unsigned seed) {
  const auto data =
      testing::draw_measurements(testing::cycling_temperature(ranges),
                                 testing::kSyntheticDistanceMm, testing::cubic_bias, truth, seed);
  return {
      data.range.array() - testing::kSyntheticDistanceMm,
      Basis::polynomial(3, data.junction_temperature_c).design_matrix(data.junction_temperature_c)};
}

// exp, log and erfc agree element by element with the standard library's on both paths, for every
// length (the AVX2 path takes the last n mod 4 elements apart), across their whole range.
TEST_F(VectorMath, BothPathsMatchTheStandardLibraryOnEveryLength) {
  for (const VectorMathPath path : {VectorMathPath::Portable, VectorMathPath::Avx2Fma}) {
    for (Eigen::Index n = 1; n <= 11; ++n) {
      const Eigen::ArrayXd x = uniform(n, -700.0, 700.0, static_cast<unsigned>(n));
      Eigen::ArrayXd e = x;
      exp_in_place(e.data(), n, path);
      const Eigen::ArrayXd positive = uniform(n, 1e-300, 1e3, static_cast<unsigned>(n) + 100);
      Eigen::ArrayXd l = positive;
      log_in_place(l.data(), n, path);
      // erfc over the range where it is above the smallest normal double (z < 26.5).
      const Eigen::ArrayXd z = uniform(n, -6.0, 26.0, static_cast<unsigned>(n) + 200);
      Eigen::ArrayXd c = z;
      erfc_in_place(c.data(), n, path);
      for (Eigen::Index i = 0; i < n; ++i) {
        EXPECT_NEAR(e[i], std::exp(x[i]), kElementRelative * std::exp(x[i]))
            << vector_math_path_name(path) << " exp(" << x[i] << ")";
        EXPECT_NEAR(l[i], std::log(positive[i]), kElementRelative * std::abs(std::log(positive[i])))
            << vector_math_path_name(path) << " log(" << positive[i] << ")";
        EXPECT_NEAR(c[i], std::erfc(z[i]), kElementRelative * std::erfc(z[i]))
            << vector_math_path_name(path) << " erfc(" << z[i] << ")";
      }
    }
  }
}

TEST_F(VectorMath, BothPathsKeepTheSpecialValues) {
  for (const VectorMathPath path : {VectorMathPath::Portable, VectorMathPath::Avx2Fma}) {
    Eigen::ArrayXd e(5);
    e << -kInfinity, 0.0, -800.0, kInfinity, std::numeric_limits<double>::quiet_NaN();
    exp_in_place(e.data(), e.size(), path);
    // Underflow: 0, or on Eigen's SSE2 path a subnormal below the smallest normal double.
    EXPECT_LT(e[0], std::numeric_limits<double>::min()) << vector_math_path_name(path);
    EXPECT_GE(e[0], 0.0) << vector_math_path_name(path);
    EXPECT_EQ(e[1], 1.0) << vector_math_path_name(path);
    EXPECT_LT(e[2], std::numeric_limits<double>::min()) << vector_math_path_name(path);
    EXPECT_GE(e[2], 0.0) << vector_math_path_name(path);
    EXPECT_EQ(e[3], kInfinity) << vector_math_path_name(path);
    EXPECT_TRUE(std::isnan(e[4])) << vector_math_path_name(path);
    Eigen::ArrayXd l(3);
    l << 0.0, 1.0, kInfinity;
    log_in_place(l.data(), l.size(), path);
    EXPECT_EQ(l[0], -kInfinity) << vector_math_path_name(path);
    EXPECT_EQ(l[1], 0.0) << vector_math_path_name(path);
    EXPECT_EQ(l[2], kInfinity) << vector_math_path_name(path);
    Eigen::ArrayXd c(3);
    c << -kInfinity, 0.0, kInfinity;
    erfc_in_place(c.data(), c.size(), path);
    EXPECT_EQ(c[0], 2.0) << vector_math_path_name(path);
    EXPECT_EQ(c[1], 1.0) << vector_math_path_name(path);
    EXPECT_EQ(c[2], 0.0) << vector_math_path_name(path);
  }
}

// The E-step of Eq. 18 and the fused sweep of the exact M-step on the same data under each path:
// the log-likelihood to 1e-12 relative, the responsibilities and the M-step's sums as closely.
TEST_F(VectorMath, TheEStepsGiveTheSameLikelihoodOnEitherPath) {
  const auto truth = testing::mixture({-1.4, 0.0, 1.5}, {0.6, 0.55, 0.7}, {0.3, 0.4, 0.3});
  const MixtureRecord record = draw_mixture_record(truth, 20011, 7);
  const Eigen::VectorXd& y = record.y;
  const Eigen::MatrixXd& h = record.h;
  const Eigen::VectorXd theta = Eigen::VectorXd::Zero(h.cols());
  const Eigen::VectorXd residual = y;
  struct Run {
    double e_step = 0.0;
    Eigen::MatrixXd responsibilities;
    Eigen::VectorXd densities;
    Eigen::VectorXd rounded;
    ExactStepSums sums;
    Eigen::MatrixXd sweep_responsibilities;
  };
  const auto run = [&](VectorMathPath path) {
    pin_vector_math_path(path);
    Run r;
    r.e_step = mixture_e_step(residual, truth, r.responsibilities);
    r.densities = mixture_log_densities(residual, truth);
    r.rounded = rounded_mixture_log_probabilities(residual.array().round().matrix(), truth, 1.0);
    r.sums = exact_step_sweep(h, y, theta, truth, Eigen::RowVectorXd::Zero(h.cols()),
                              r.sweep_responsibilities);
    return r;
  };
  const Run portable = run(VectorMathPath::Portable);
  const Run avx2 = run(VectorMathPath::Avx2Fma);
  EXPECT_NEAR(avx2.e_step, portable.e_step, kSumRelative * std::abs(portable.e_step));
  EXPECT_NEAR(avx2.sums.log_likelihood, portable.sums.log_likelihood,
              kSumRelative * std::abs(portable.sums.log_likelihood));
  EXPECT_NEAR(avx2.sums.log_likelihood, portable.e_step, kSumRelative * std::abs(portable.e_step));
  EXPECT_LE((avx2.responsibilities - portable.responsibilities).cwiseAbs().maxCoeff(),
            kElementRelative);
  EXPECT_LE((avx2.sweep_responsibilities - portable.sweep_responsibilities).cwiseAbs().maxCoeff(),
            kElementRelative);
  EXPECT_LE(
      ((avx2.densities - portable.densities).array() / portable.densities.array()).abs().maxCoeff(),
      kElementRelative);
  EXPECT_LE(((avx2.rounded - portable.rounded).array() / portable.rounded.array()).abs().maxCoeff(),
            kElementRelative);
  EXPECT_NEAR(avx2.rounded.sum(), portable.rounded.sum(),
              kSumRelative * std::abs(portable.rounded.sum()));
  EXPECT_LE((avx2.sums.gram - portable.sums.gram).cwiseAbs().maxCoeff(),
            kSumRelative * portable.sums.gram.cwiseAbs().maxCoeff());
  EXPECT_LE((avx2.sums.mode_sums - portable.sums.mode_sums).cwiseAbs().maxCoeff(),
            kSumRelative * portable.sums.mode_sums.cwiseAbs().maxCoeff());
  // The E-step's own sums (the AVX2 sweep accumulates them in its kernel).
  for (const auto& [a, b] : {std::pair{&avx2.sums.gram_rhs, &portable.sums.gram_rhs},
                             std::pair{&avx2.sums.mode_weight, &portable.sums.mode_weight},
                             std::pair{&avx2.sums.mode_target, &portable.sums.mode_target},
                             std::pair{&avx2.sums.mass, &portable.sums.mass}}) {
    EXPECT_LE((*a - *b).cwiseAbs().maxCoeff(), kSumRelative * b->cwiseAbs().maxCoeff());
  }
}

// A whole fit converges to the same maximum on either path.
TEST_F(VectorMath, TrainingReachesTheSameMaximumOnEitherPath) {
  const auto truth = testing::mixture({-2.0, 0.0, 2.5}, {0.6, 0.55, 0.7}, {0.3, 0.4, 0.3});
  const MixtureRecord record = draw_mixture_record(truth, 12000, 11);
  const Eigen::VectorXd& y = record.y;
  const Eigen::MatrixXd& h = record.h;
  EmTrainOptions options;
  options.modes = 3;
  options.record_trace = false;
  options.weight_tolerance = 1e-10;
  options.log_likelihood_tolerance = 1e-13;
  pin_vector_math_path(VectorMathPath::Portable);
  const EmTrainResult portable = train_em(h, y, options);
  pin_vector_math_path(VectorMathPath::Avx2Fma);
  const EmTrainResult avx2 = train_em(h, y, options);
  ASSERT_TRUE(portable.converged);
  ASSERT_TRUE(avx2.converged);
  EXPECT_NEAR(avx2.log_likelihood, portable.log_likelihood,
              kSumRelative * std::abs(portable.log_likelihood));
  EXPECT_LE((avx2.theta - portable.theta).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace tofcomp::core
