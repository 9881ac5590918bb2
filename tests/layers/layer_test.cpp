// The layers of docs/architecture.md hold in the source tree: no #include runs against them.
#include <gtest/gtest.h>

#include "tests/layers/layer_rules.hpp"

namespace tofcomp::layers {
namespace {

TEST(Layers, NoIncludeRunsAgainstTheLayers) {
  const auto violations = find_layer_violations(TOFCOMP_SOURCE_ROOT, project_rules());
  for (const auto& v : violations) ADD_FAILURE() << describe(v, project_rules());
  EXPECT_TRUE(violations.empty());
}

// The check can fail: tests/layers/fixture holds a tree with one wrong-way include (core/ naming
// daemon/) beside right-way ones (io/ naming core/, cli/ naming io/ and a system header).
TEST(Layers, FindsTheWrongWayIncludeOfTheFixture) {
  const auto violations = find_layer_violations(
      std::string(TOFCOMP_SOURCE_ROOT) + "/tests/layers/fixture", project_rules());
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_EQ(violations[0].file, std::filesystem::path("core/wrong_way.hpp"));
  EXPECT_EQ(violations[0].line, 4);
  EXPECT_EQ(violations[0].from, "core");
  EXPECT_EQ(violations[0].to, "daemon");
  EXPECT_EQ(describe(violations[0], project_rules()),
            "core/wrong_way.hpp:4: core may not include daemon/ (core may use: core)");
}

// Every product folder has a rule and may use itself; nothing may use cli/ or daemon/ but they.
TEST(Layers, TheRulesPointOneWay) {
  for (const auto& [folder, allowed] : project_rules()) {
    EXPECT_TRUE(allowed.count(folder)) << folder;
    if (folder != "cli") {
      EXPECT_FALSE(allowed.count("cli")) << folder;
    }
    if (folder != "daemon") {
      EXPECT_FALSE(allowed.count("daemon")) << folder;
    }
    // A rule names only folders that have rules, and never one that may use it back.
    for (const std::string& used : allowed) {
      ASSERT_TRUE(project_rules().count(used)) << folder << " uses " << used;
      if (used != folder) {
        EXPECT_FALSE(project_rules().at(used).count(folder)) << folder << " <-> " << used;
      }
    }
  }
}

}  // namespace
}  // namespace tofcomp::layers
