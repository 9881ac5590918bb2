// The bounds of numeric options (cli/number_checks.hpp): what they accept, and that a refusal
// says the bound in a few words instead of CLI11's six-decimal, 300-digit range.
#include "cli/number_checks.hpp"

#include <gtest/gtest.h>

namespace tofcomp::cli {
namespace {

// The validator's answer for text: empty when it accepts it.
std::string check(const CLI::Validator& validator, std::string text) { return validator(text); }

TEST(NumberChecks, AtLeast) {
  EXPECT_EQ(check(at_least(1), "1"), "");
  EXPECT_EQ(check(at_least(1), "10"), "");
  EXPECT_EQ(check(at_least(1), "0"), "must be at least 1, not 0");
  EXPECT_EQ(check(at_least(0), "-0.5"), "must be at least 0, not -0.5");
}

TEST(NumberChecks, GreaterThan) {
  EXPECT_EQ(check(greater_than(0), "0.001"), "");
  EXPECT_EQ(check(greater_than(0), "0"), "must be greater than 0, not 0");
}

TEST(NumberChecks, Between) {
  EXPECT_EQ(check(between(0.05, 0.95), "0.05"), "");
  EXPECT_EQ(check(between(0.05, 0.95), "0.95"), "");
  EXPECT_EQ(check(between(0.05, 0.95), "1"), "must be between 0.05 and 0.95, not 1");
  EXPECT_EQ(check(between(1, 1000000), "0"), "must be between 1 and 1000000, not 0");
  EXPECT_EQ(check(between(1e-9, 0.5), "0"), "must be between 1e-09 and 0.5, not 0");
}

TEST(NumberChecks, TextThatIsNotANumberIsNamed) {
  EXPECT_EQ(check(at_least(1), "ten"), "'ten' is not a number");
  EXPECT_NE(check(between(0, 1), "nan"), "");
}

}  // namespace
}  // namespace tofcomp::cli
