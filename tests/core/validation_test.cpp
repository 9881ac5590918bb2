#include "core/validation.hpp"

#include <gtest/gtest.h>

#include <limits>

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

}  // namespace
}  // namespace tofcomp::core
