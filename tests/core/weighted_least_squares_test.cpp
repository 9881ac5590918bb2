#include "core/weighted_least_squares.hpp"

#include <gtest/gtest.h>

#include <Eigen/QR>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

TEST(WeightedLeastSquares, GramIsHtWH) {
  const Eigen::MatrixXd h = Eigen::MatrixXd::Random(50, 4);
  const Eigen::VectorXd w = Eigen::VectorXd::Random(50).cwiseAbs();
  Eigen::MatrixXd scratch;
  const Eigen::MatrixXd g = weighted_gram(h, w, scratch);
  const Eigen::MatrixXd direct = h.transpose() * w.asDiagonal() * h;
  EXPECT_LT((g - direct).norm(), 1e-12 * direct.norm());
}

// The normal-equation solution equals a QR solution of the weighted problem.
TEST(WeightedLeastSquares, SolutionMatchesQr) {
  const Eigen::MatrixXd h = Eigen::MatrixXd::Random(40, 3);
  const Eigen::VectorXd w = Eigen::VectorXd::Random(40).cwiseAbs().array() + 0.1;
  const Eigen::VectorXd y = Eigen::VectorXd::Random(40);
  Eigen::MatrixXd scratch;
  const Eigen::VectorXd x =
      solve_normal_equations(weighted_gram(h, w, scratch), h.transpose() * w.cwiseProduct(y), "G");
  const Eigen::VectorXd sw = w.cwiseSqrt();
  const Eigen::VectorXd qr = (sw.asDiagonal() * h).colPivHouseholderQr().solve(sw.cwiseProduct(y));
  EXPECT_LT((x - qr).norm(), 1e-10);
}

TEST(WeightedLeastSquares, SingularSystemIsANamedError) {
  Eigen::MatrixXd h(5, 2);
  h.col(0).setOnes();
  h.col(1).setConstant(2.0);  // collinear columns
  Eigen::MatrixXd scratch;
  const Eigen::MatrixXd g = weighted_gram(h, Eigen::VectorXd::Ones(5), scratch);
  try {
    solve_normal_equations(g, Eigen::Vector2d(1, 1), "HᵀC⁻¹H");
    FAIL() << "expected NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("HᵀC⁻¹H is singular"), std::string::npos) << e.what();
  }
  Eigen::MatrixXd zero_column = h;
  zero_column.col(1).setZero();
  EXPECT_THROW(solve_normal_equations(weighted_gram(zero_column, Eigen::VectorXd::Ones(5), scratch),
                                      Eigen::Vector2d(1, 1), "G"),
               NumericalError);
}

}  // namespace
}  // namespace tofcomp::core
