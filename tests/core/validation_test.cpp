#include "core/validation.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

TEST(Validation, RejectsNaNAndNamesTheIndex) {
  Eigen::VectorXd v(3);
  v << 1.0, std::numeric_limits<double>::quiet_NaN(), 2.0;
  try {
    require_finite(v, "y");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("y[1]"), std::string::npos) << e.what();
  }
}

TEST(Validation, RejectsInfInMatrix) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(2, 2);
  m(1, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(require_finite(m, "H"), InvalidInput);
}

TEST(Validation, AcceptsFiniteAndMatchingLengths) {
  EXPECT_NO_THROW(require_finite(Eigen::VectorXd::Ones(4), "y"));
  EXPECT_NO_THROW(require_same_length(4, "y", 4, "t"));
  EXPECT_THROW(require_same_length(4, "y", 3, "t"), InvalidInput);
  EXPECT_THROW(require_positive(0.0, "R1"), InvalidInput);
  EXPECT_THROW(require_positive(-1.0, "R1"), InvalidInput);
  EXPECT_NO_THROW(require_positive(1e-9, "R1"));
}

// The vectorized check against the element-wise definition: every non-finite kind at every place
// of a block of a larger matrix (not contiguous), found and named; values whose sum overflows pass.
TEST(Validation, EveryNonFiniteValueOfABlockIsFoundAndNamed) {
  const double kinds[] = {std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::infinity(),
                          -std::numeric_limits<double>::infinity()};
  Eigen::MatrixXd big = Eigen::MatrixXd::Constant(9, 5, 0.5);
  for (const double bad : kinds) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      for (Eigen::Index r = 0; r < 7; ++r) {
        Eigen::MatrixXd m = big;
        m(1 + r, 1 + c) = bad;
        m(0, 0) = bad;  // outside the block: never read
        try {
          require_finite(m.block(1, 1, 7, 3), "H");
          FAIL() << "expected InvalidInput at (" << r << ", " << c << ")";
        } catch (const InvalidInput& e) {
          const std::string where = "H(" + std::to_string(r) + ", " + std::to_string(c) + ")";
          EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
        }
      }
    }
  }
  const double largest = std::numeric_limits<double>::max();
  EXPECT_NO_THROW(require_finite(Eigen::MatrixXd::Constant(33, 3, largest), "H"));
  EXPECT_NO_THROW(require_finite(Eigen::VectorXd::Constant(33, -largest), "y"));
}

}  // namespace
}  // namespace tofcomp::core
