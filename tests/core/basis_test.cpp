#include "core/basis.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

double condition_number(const Eigen::MatrixXd& m) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  const auto& s = svd.singularValues();
  return s[0] / s[s.size() - 1];
}

Eigen::VectorXd evenly_spaced(Eigen::Index n, double lo, double hi) {
  return Eigen::VectorXd::LinSpaced(n, lo, hi);
}

TEST(Basis, LegendreColumnsMatchClosedForms) {
  const Basis basis({BasisTerm{BasisKind::Polynomial, 4, PolynomialForm::Legendre, 0.0}},
                    TemperatureScaling{26.0, 2.0});
  Eigen::RowVectorXd row(4);
  basis.row(27.0, row);  // z = 0.5
  const double z = 0.5;
  EXPECT_NEAR(row[0], z, 1e-15);
  EXPECT_NEAR(row[1], (3 * z * z - 1) / 2, 1e-15);
  EXPECT_NEAR(row[2], (5 * z * z * z - 3 * z) / 2, 1e-15);
  EXPECT_NEAR(row[3], (35 * std::pow(z, 4) - 30 * z * z + 3) / 8, 1e-15);
}

TEST(Basis, RawPowerIsEquation9) {
  const Basis basis({BasisTerm{BasisKind::Polynomial, 3, PolynomialForm::RawPower, 0.0}},
                    TemperatureScaling{});
  const Eigen::MatrixXd h = basis.design_matrix(Eigen::Vector2d(2.0, 25.0));
  EXPECT_DOUBLE_EQ(h(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(h(0, 2), 8.0);
  EXPECT_DOUBLE_EQ(h(1, 1), 625.0);
  EXPECT_DOUBLE_EQ(h(1, 2), 15625.0);
}

TEST(Basis, FourierIsEquation11AtHighOrder) {
  const double f0 = 0.037;
  const Basis basis = Basis::fourier(60, f0);
  ASSERT_EQ(basis.columns(), 120);
  Eigen::RowVectorXd row(120);
  const double t = 26.3;
  basis.row(t, row);
  for (int n = 1; n <= 60; ++n) {
    EXPECT_NEAR(row[2 * (n - 1)], std::cos(2 * std::numbers::pi * n * f0 * t), 1e-12) << n;
    EXPECT_NEAR(row[2 * (n - 1) + 1], std::sin(2 * std::numbers::pi * n * f0 * t), 1e-12) << n;
  }
}

TEST(Basis, ComposedBasisConcatenatesTerms) {
  const Basis basis({BasisTerm{BasisKind::Polynomial, 2, PolynomialForm::Legendre, 0.0},
                     BasisTerm{BasisKind::Fourier, 1, PolynomialForm::Legendre, 0.1}},
                    TemperatureScaling{25.0, 1.0});
  ASSERT_EQ(basis.columns(), 4);
  Eigen::RowVectorXd row(4);
  basis.row(26.0, row);
  EXPECT_NEAR(row[0], 1.0, 1e-15);
  EXPECT_NEAR(row[1], 1.0, 1e-15);
  EXPECT_NEAR(row[2], std::cos(2 * std::numbers::pi * 0.1 * 26.0), 1e-15);
  EXPECT_EQ(basis.describe(), "polynomial(2, legendre)+fourier(1, f0=0.1)");
}

// The design matrix, built a column at a time, holds row()'s values exactly, row by row: every
// form (Legendre, raw powers, Fourier) alone and composed, at orders 1 to 16.
TEST(Basis, DesignMatrixIsRowsExactly) {
  const Eigen::VectorXd t = evenly_spaced(37, 18.5, 41.0);
  std::vector<Basis> bases;
  for (int order : {1, 2, 3, 7, 16}) {
    bases.push_back(Basis::polynomial(order, t));
    bases.push_back(Basis::polynomial(order, t, PolynomialForm::RawPower));
    bases.push_back(Basis::fourier(order, 0.037));
  }
  bases.push_back(Basis({BasisTerm{BasisKind::Polynomial, 5, PolynomialForm::Legendre, 0.0},
                         BasisTerm{BasisKind::Fourier, 3, PolynomialForm::Legendre, 0.1},
                         BasisTerm{BasisKind::Polynomial, 2, PolynomialForm::RawPower, 0.0}},
                        TemperatureScaling{27.0, 6.0}));
  for (const Basis& basis : bases) {
    const Eigen::MatrixXd h = basis.design_matrix(t);
    ASSERT_EQ(h.rows(), t.size());
    ASSERT_EQ(h.cols(), basis.columns());
    Eigen::RowVectorXd row(basis.columns());
    for (Eigen::Index k = 0; k < t.size(); ++k) {
      basis.row(t[k], row);
      for (Eigen::Index j = 0; j < row.size(); ++j) {
        ASSERT_EQ(h(k, j), row[j]) << basis.describe() << " at row " << k << ", column " << j;
      }
    }
  }
}

// Order 16 on the paper's temperature range: the Legendre form is well conditioned, the raw
// form of Eq. 9 is not (its columns span 25^1..25^16).
TEST(Basis, LegendreOrder16IsWellConditionedRawIsNot) {
  const Eigen::VectorXd t = evenly_spaced(2000, 24.8, 28.8);
  const Eigen::MatrixXd legendre = Basis::polynomial(16, t).design_matrix(t);
  const Eigen::MatrixXd raw = Basis::polynomial(16, t, PolynomialForm::RawPower).design_matrix(t);
  EXPECT_LT(condition_number(legendre), 1e4);
  EXPECT_GT(condition_number(raw), 1e15);
}

// Both forms with a constant span the polynomials of degree ≤ N, so they describe one model.
TEST(Basis, LegendreAndRawSpanTheSameModel) {
  const Eigen::VectorXd t = evenly_spaced(200, 24.8, 28.8);
  const Eigen::MatrixXd legendre = Basis::polynomial(4, t).design_matrix(t);
  const Eigen::MatrixXd raw = Basis::polynomial(4, t, PolynomialForm::RawPower).design_matrix(t);
  Eigen::MatrixXd with_constant(t.size(), 5);
  with_constant << Eigen::VectorXd::Ones(t.size()), legendre;
  const auto qr = with_constant.colPivHouseholderQr();
  for (int c = 0; c < 4; ++c) {
    const Eigen::VectorXd coef = qr.solve(raw.col(c));
    EXPECT_LT((with_constant * coef - raw.col(c)).norm() / raw.col(c).norm(), 1e-9) << c;
  }
}

TEST(Basis, ScalingSpansTheTrainingRange) {
  const auto s = TemperatureScaling::spanning(Eigen::Vector3d(25.0, 29.0, 27.0));
  EXPECT_DOUBLE_EQ(s.center_c, 27.0);
  EXPECT_DOUBLE_EQ(s.half_range_c, 2.0);
  const auto constant = TemperatureScaling::spanning(Eigen::Vector2d(25.0, 25.0));
  EXPECT_GT(constant.half_range_c, 0.0);
}

TEST(Basis, RejectsBadInput) {
  const Eigen::VectorXd t = evenly_spaced(10, 24.0, 26.0);
  EXPECT_THROW(Basis::polynomial(0, t), InvalidInput);
  EXPECT_THROW(Basis::fourier(3, 0.0), InvalidInput);
  EXPECT_THROW(Basis::fourier(3, -1.0), InvalidInput);
  EXPECT_THROW(Basis({}, TemperatureScaling{}), InvalidInput);
  Eigen::VectorXd bad = t;
  bad[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Basis::polynomial(2, t).design_matrix(bad), InvalidInput);
  EXPECT_THROW(Basis::polynomial(2, bad), InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
