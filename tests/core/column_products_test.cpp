// The exact EM step's products over a chunk of ranges (core/column_products.hpp) on both paths,
// against sums written out element by element in long double: every shape the kernels split
// (ranges not a multiple of the 4 lanes, more ranges than a pass keeps in cache, fewer than a
// register holds; columns not a multiple of the tile's 4 and 2), columns further apart than the
// rows (a chunk's top rows), and the lower Gram triangle touched alone.
#include "core/column_products.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace tofcomp::core {
namespace {

// Sums of a few hundred products of values in [−1, 1]: each path's rounding is far below this.
constexpr double kAbsolute = 1e-12;
// A value no kernel writes: what must stay untouched keeps it.
constexpr double kUntouched = 12345.0;

Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = u(rng);
  }
  return m;
}

std::vector<VectorMathPath> paths() {
  std::vector<VectorMathPath> out{VectorMathPath::Portable};
  if (vector_math_path_available(VectorMathPath::Avx2Fma)) out.push_back(VectorMathPath::Avx2Fma);
  return out;
}

// Ranges: fewer than a register, not a multiple of 4, beyond one cached pass (128) and a chunk.
const std::vector<Eigen::Index> kColumnLengths{1, 3, 4, 7, 129, 512, 515};
const std::vector<Eigen::Index> kColumns{1, 2, 3, 4, 5, 7, 9, 17};
// Extra rows below the block the kernels see: columns further apart than its rows.
constexpr Eigen::Index kExtraRows = 5;

TEST(ColumnProducts, LowerGramIsTheSumOfProductsAndLeavesTheUpperTriangle) {
  for (const VectorMathPath path : paths()) {
    for (const Eigen::Index n : kColumnLengths) {
      for (const Eigen::Index p : kColumns) {
        const Eigen::MatrixXd storage = random_matrix(n + kExtraRows, p, 7);
        const auto x = storage.topRows(n);
        Eigen::MatrixXd gram = Eigen::MatrixXd::Constant(p, p, kUntouched);
        gram.triangularView<Eigen::Lower>().setConstant(1.0);  // added to, not overwritten
        add_lower_gram(x, gram, path);
        for (Eigen::Index j = 0; j < p; ++j) {
          for (Eigen::Index i = 0; i < p; ++i) {
            if (i < j) {
              EXPECT_EQ(gram(i, j), kUntouched) << "upper (" << i << ", " << j << ") touched";
              continue;
            }
            long double sum = 1.0L;
            for (Eigen::Index k = 0; k < n; ++k) sum += static_cast<long double>(x(k, i)) * x(k, j);
            EXPECT_NEAR(gram(i, j), static_cast<double>(sum), kAbsolute)
                << vector_math_path_name(path) << " n " << n << " p " << p << " (" << i << ", " << j
                << ")";
          }
        }
      }
    }
  }
}

TEST(ColumnProducts, CrossProductsAreTheSumsOfProducts) {
  for (const VectorMathPath path : paths()) {
    for (const Eigen::Index n : kColumnLengths) {
      for (const Eigen::Index p : kColumns) {
        for (const Eigen::Index q : {1, 2, 3}) {
          const Eigen::MatrixXd xs = random_matrix(n + kExtraRows, p, 11);
          const Eigen::MatrixXd zs = random_matrix(n + kExtraRows, q, 13);
          const auto x = xs.topRows(n);
          const auto z = zs.topRows(n);
          Eigen::MatrixXd out = Eigen::MatrixXd::Constant(p, q, 0.5);
          add_cross_products(x, z, out, path);
          for (Eigen::Index j = 0; j < q; ++j) {
            for (Eigen::Index i = 0; i < p; ++i) {
              long double sum = 0.5L;
              for (Eigen::Index k = 0; k < n; ++k)
                sum += static_cast<long double>(x(k, i)) * z(k, j);
              EXPECT_NEAR(out(i, j), static_cast<double>(sum), kAbsolute)
                  << vector_math_path_name(path) << " n " << n << " p " << p << " q " << q;
            }
          }
        }
      }
    }
  }
}

TEST(ColumnProducts, ResidualAndCentredRowsAreTheirDefinitions) {
  for (const VectorMathPath path : paths()) {
    for (const Eigen::Index n : kColumnLengths) {
      for (const Eigen::Index p : kColumns) {
        const Eigen::MatrixXd hs = random_matrix(n + kExtraRows, p, 17);
        const auto h = hs.topRows(n);
        const Eigen::VectorXd theta = random_matrix(p, 1, 19);
        const Eigen::VectorXd y = random_matrix(n, 1, 23);
        const Eigen::RowVectorXd centre = random_matrix(1, p, 29);
        const Eigen::VectorXd scale = random_matrix(n, 1, 31).array().abs();
        Eigen::VectorXd e = y;
        subtract_product(h, theta, e, path);
        Eigen::MatrixXd xs = Eigen::MatrixXd::Constant(n + kExtraRows, p, kUntouched);
        scale_centred_rows(h, centre, scale, xs.topRows(n), path);
        for (Eigen::Index k = 0; k < n; ++k) {
          long double fitted = 0.0L;
          for (Eigen::Index i = 0; i < p; ++i)
            fitted += static_cast<long double>(h(k, i)) * theta[i];
          EXPECT_NEAR(e[k], static_cast<double>(y[k] - fitted), kAbsolute);
          for (Eigen::Index i = 0; i < p; ++i) {
            EXPECT_NEAR(xs(k, i), (h(k, i) - centre[i]) * scale[k], kAbsolute);
          }
        }
        EXPECT_TRUE((xs.bottomRows(kExtraRows).array() == kUntouched).all())
            << "rows below the block written";
      }
    }
  }
}

}  // namespace
}  // namespace tofcomp::core
