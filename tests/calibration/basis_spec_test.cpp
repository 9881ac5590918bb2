#include "calibration/basis_spec.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

const Eigen::VectorXd kTemps = Eigen::VectorXd::LinSpaced(10, 24.8, 28.8);

TEST(BasisSpec, ParsesTermsAndScales) {
  const core::Basis b = parse_basis("polynomial:3+fourier:2:0.125", kTemps);
  EXPECT_EQ(b.columns(), 7);
  EXPECT_EQ(b.describe(), "polynomial(3, legendre)+fourier(2, f0=0.125)");
  EXPECT_DOUBLE_EQ(b.scaling().center_c, 26.8);
  EXPECT_DOUBLE_EQ(b.scaling().half_range_c, 2.0);
  EXPECT_EQ(parse_basis("polynomial:16:raw", kTemps).terms()[0].form,
            core::PolynomialForm::RawPower);
}

TEST(BasisSpec, ExpandsRanges) {
  const auto c = parse_candidates({"polynomial:1..4", "fourier:1..2:0.25"}, kTemps);
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(c[3].describe(), "polynomial(4, legendre)");
  EXPECT_EQ(c[5].describe(), "fourier(2, f0=0.25)");
}

TEST(BasisSpec, ErrorsNameTheTerm) {
  for (const char* bad : {"poly:3", "polynomial", "polynomial:0", "polynomial:x",
                          "polynomial:3:cubic", "fourier:2", "fourier:2:abc", "polynomial:4..2"}) {
    try {
      parse_candidates({bad}, kTemps);
      ADD_FAILURE() << bad;
    } catch (const core::InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace tofcomp::calibration
