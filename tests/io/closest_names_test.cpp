// "Did you mean" (io/closest_names.hpp): the edit distance against distances worked by hand, and
// which names are offered for which typos.
#include "io/closest_names.hpp"

#include <gtest/gtest.h>

namespace tofcomp::io {
namespace {

TEST(EditDistance, CountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);  // k→s, e→i, +g
  EXPECT_EQ(edit_distance("evalute", "evaluate"), 1u);
  EXPECT_EQ(edit_distance("--figure", "--figures"), 1u);
  EXPECT_EQ(edit_distance("subscirbe", "subscribe"), 1u);  // one swap of neighbours
  EXPECT_EQ(edit_distance("ab", "ba"), 1u);
}

TEST(ClosestNames, OffersTheNearestKnownNames) {
  const std::vector<std::string> subcommands{"simulate", "train", "test", "evaluate", "emulate"};
  EXPECT_EQ(closest_names("evalute", subcommands), std::vector<std::string>{"evaluate"});
  EXPECT_EQ(closest_names("trian", subcommands), std::vector<std::string>{"train"});
  const std::vector<std::string> options{"--figures", "--json", "--stride", "--windows"};
  EXPECT_EQ(closest_names("--figure", options), std::vector<std::string>{"--figures"});
  EXPECT_EQ(closest_names("--jsno", options), std::vector<std::string>{"--json"});
}

TEST(ClosestNames, OffersEveryNameAtTheSmallestDistance) {
  EXPECT_EQ(closest_names("tast", {"test", "task", "toast", "train"}),
            (std::vector<std::string>{"test", "task", "toast"}));
}

TEST(ClosestNames, OffersNothingForFarOrShortNamesOrAnExactOne) {
  const std::vector<std::string> names{"simulate", "evaluate", "-n", "-o", "--json"};
  EXPECT_TRUE(closest_names("calibrate", names).empty());
  EXPECT_TRUE(closest_names("-m", names).empty());  // one letter: every short option is one edit
  EXPECT_TRUE(closest_names("--js", names).empty());
  EXPECT_TRUE(closest_names("evaluate", names).empty());
}

}  // namespace
}  // namespace tofcomp::io
