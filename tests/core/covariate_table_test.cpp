// core/covariate_table: a term's constants come from the ranges it is made on, and a linear mean
// term holds its value beyond the covariate range it was made on (the answers follow from the
// definitions: f(c) = (clamp(c, low, high) − centre) / scale).
#include "core/covariate_table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

constexpr Eigen::Index kTableRanges = 100;

// Time 0..99 s, the time since power-on the same; the junction 20 °C rising 0.1 °C a range,
// but for the last ten ranges, which jump to 60 °C.
CovariateTable table() {
  CovariateSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(kTableRanges, 0.0, static_cast<double>(kTableRanges - 1));
  s.junction_c = 20.0 + 0.1 * s.time_s.array();
  s.junction_c.tail(10).setConstant(60.0);
  s.time_since_power_on_s = s.time_s;
  return CovariateTable(std::move(s));
}

std::vector<Eigen::Index> first_ninety() {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index k = 0; k < 90; ++k) rows.push_back(k);
  return rows;
}

TEST(CovariateTerm, ALinearMeanTermsRangeIsThatOfTheRowsItIsMadeOn) {
  const CovariateTable c = table();
  const Term on_rows = c.make_term(Parameter::Bias, Covariate::JunctionTemperature, Form::Linear,
                                   -1, 0.0, first_ninety());
  EXPECT_DOUBLE_EQ(on_rows.covariate_low, 20.0);
  EXPECT_NEAR(on_rows.covariate_high, 28.9, 1e-12);
  EXPECT_NEAR(on_rows.centre, 24.45, 1e-12);  // the mean of 20.0, 20.1, ..., 28.9
  const Term on_all =
      c.make_term(Parameter::Bias, Covariate::JunctionTemperature, Form::Linear, -1, 0.0);
  EXPECT_DOUBLE_EQ(on_all.covariate_high, 60.0);
}

TEST(CovariateTerm, ALinearMeanTermHoldsItsValueBeyondItsRange) {
  const CovariateTable c = table();
  const Term term = c.make_term(Parameter::Bias, Covariate::JunctionTemperature, Form::Linear, -1,
                                0.0, first_ninety());
  const Eigen::MatrixXd columns = c.columns(term);
  const double at_high = (28.9 - term.centre) / term.scale;
  for (Eigen::Index k = 90; k < kTableRanges; ++k) EXPECT_NEAR(columns(k, 0), at_high, 1e-12);
  // Inside the range: the standardized covariate itself.
  EXPECT_NEAR(columns(50, 0), (25.0 - term.centre) / term.scale, 1e-12);
  // Below it: the low end's value.
  Eigen::RowVectorXd row(1);
  term_design_row(term, -40.0, row);
  EXPECT_NEAR(row[0], (20.0 - term.centre) / term.scale, 1e-12);
}

// The time since the start always leaves the range a term was fitted on, and a linear drift
// goes on: a linear time term gets no range.
TEST(CovariateTerm, ALinearDriftInTimeGoesOnBeyondTheDataItWasFittedOn) {
  const CovariateTable c = table();
  const Term linear =
      c.make_term(Parameter::Bias, Covariate::Time, Form::Linear, -1, 0.0, first_ninety());
  EXPECT_EQ(linear.covariate_low, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(linear.covariate_high, std::numeric_limits<double>::infinity());
  Eigen::RowVectorXd row(1);
  term_design_row(linear, 2.0, row);  // 2 h, beyond the first 89 s it was fitted on
  EXPECT_NEAR(row[0], (2.0 - linear.centre) / linear.scale, 1e-12);
}

// A linear bias on the time, centre 0 and scale 1, without a range.
Term linear_time_bias() {
  Term term;
  term.parameter = Parameter::Bias;
  term.covariate = Covariate::Time;
  term.form = Form::Linear;
  return term;
}

TEST(CovariateTerm, ATermWithoutARangeIsUnbounded) {
  Term term = linear_time_bias();
  term.centre = 1.0;
  term.scale = 2.0;
  term.validate();
  Eigen::RowVectorXd row(1);
  term_design_row(term, 101.0, row);
  EXPECT_DOUBLE_EQ(row[0], 50.0);
}

TEST(CovariateTerm, ARangeWhoseEndsAreReversedOrNotANumberIsRefused) {
  Term term = linear_time_bias();
  term.covariate_low = 2.0;
  term.covariate_high = 1.0;
  EXPECT_THROW(term.validate(), InvalidInput);
  term.covariate_high = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(term.validate(), InvalidInput);
}

// The smooth form's knots sit at quantiles evenly spaced from the 2nd to the 98th percentile, so
// each count of kSmoothKnotCounts holds the knots of the one before (every other knot): its hat
// functions span the coarser ones' and the models are nested. On the time since power-on, 0..99 s,
// the q-quantile is ⌊99 q⌋ s.
TEST(CovariateTerm, EachSmoothKnotCountHoldsTheKnotsOfTheOneBefore) {
  const CovariateTable c = table();
  Eigen::VectorXd coarser;
  for (const int count : kSmoothKnotCounts) {
    const Term t =
        c.make_term(Parameter::Bias, Covariate::TimeSincePowerOn, Form::Smooth, -1, 0.0, {}, count);
    ASSERT_EQ(t.knots.size(), count);
    EXPECT_EQ(t.columns(), count - 1);
    EXPECT_DOUBLE_EQ(t.knots[0], 1.0);                 // ⌊99 · 0.02⌋
    EXPECT_DOUBLE_EQ(t.knots[count - 1], 97.0);        // ⌊99 · 0.98⌋
    EXPECT_DOUBLE_EQ(t.knots[(count - 1) / 2], 49.0);  // ⌊99 · 0.5⌋
    for (Eigen::Index i = 0; i < coarser.size(); ++i) {
      EXPECT_DOUBLE_EQ(t.knots[2 * i], coarser[i]) << count << " knots, knot " << 2 * i;
    }
    coarser = t.knots;
  }
}

// A file may hold a smooth term with any count the search could have made, and no other; a count
// outside is refused with the term and the counts named.
TEST(CovariateTerm, ASmoothTermsKnotCountIsChecked) {
  Term term;
  term.parameter = Parameter::Bias;
  term.covariate = Covariate::Time;
  term.form = Form::Smooth;
  for (const int count : {kMinSmoothKnots, 4, 11, kMaxSmoothKnots}) {
    term.knots = Eigen::VectorXd::LinSpaced(count, 0.0, 10.0);
    EXPECT_NO_THROW(term.validate()) << count;
    EXPECT_EQ(term.columns(), count - 1);
  }
  for (const int count : {0, kMinSmoothKnots - 1, kMaxSmoothKnots + 1, 1000}) {
    term.knots = Eigen::VectorXd::LinSpaced(count, 0.0, 10.0);
    try {
      term.validate();
      ADD_FAILURE() << count << " knots accepted";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bias x time (smooth"), std::string::npos) << what;
      EXPECT_NE(what.find("has " + std::to_string(count)), std::string::npos) << what;
    }
  }
  const CovariateTable c = table();
  EXPECT_THROW(
      c.make_term(Parameter::Bias, Covariate::Time, Form::Smooth, -1, 0.0, {}, kMaxSmoothKnots + 1),
      InvalidInput);
}

TEST(CovariateTable, TheHeatingRateIsTheSeriesOwnWhereItBringsOne) {
  CovariateSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(kTableRanges, 0.0, static_cast<double>(kTableRanges - 1));
  s.junction_c = 20.0 + 0.1 * s.time_s.array();  // 6 °C/min by its slope
  s.time_since_power_on_s = s.time_s;
  // Without a rate of its own, the slope of the junction: 0.1 °C/s is 6 °C/min everywhere.
  const Eigen::VectorXd slope = CovariateTable(s).values(Covariate::HeatingRate);
  EXPECT_NEAR((slope.array() - 6.0).abs().maxCoeff(), 0.0, 1e-9);
  // With one (the thermal model's, calibration/junction_estimate.hpp), that one.
  s.heating_rate_c_per_min = Eigen::VectorXd::LinSpaced(kTableRanges, -1.0, 1.0);
  EXPECT_EQ(CovariateTable(s).values(Covariate::HeatingRate), s.heating_rate_c_per_min);
  // One of another length, or not a number, is refused by name.
  CovariateSeries short_rate = s;
  short_rate.heating_rate_c_per_min.conservativeResize(kTableRanges - 1);
  try {
    CovariateTable{short_rate};
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("heating rate"), std::string::npos) << e.what();
  }
  s.heating_rate_c_per_min[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(CovariateTable{s}, InvalidInput);
}

}  // namespace
}  // namespace tofcomp::core
