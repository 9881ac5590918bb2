// logging.level and logging.target: the names the configuration accepts.
#include "settings/log_settings.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"

namespace tofcomp::settings {
namespace {

TEST(LogLevelNames, EveryLevelSpdlogKnows) {
  EXPECT_EQ(parse_log_level("trace"), spdlog::level::trace);
  EXPECT_EQ(parse_log_level("debug"), spdlog::level::debug);
  EXPECT_EQ(parse_log_level("info"), spdlog::level::info);
  EXPECT_EQ(parse_log_level("warn"), spdlog::level::warn);
  EXPECT_EQ(parse_log_level("warning"), spdlog::level::warn);
  EXPECT_EQ(parse_log_level("error"), spdlog::level::err);
  EXPECT_EQ(parse_log_level("err"), spdlog::level::err);
  EXPECT_EQ(parse_log_level("critical"), spdlog::level::critical);
  EXPECT_EQ(parse_log_level("off"), spdlog::level::off);
  EXPECT_EQ(parse_log_level("Warning"), spdlog::level::warn);
}

TEST(LogLevelNames, AnUnknownNameIsAnErrorNamingIt) {
  for (const std::string bad : {"verbose", "", "inf", "info "}) {
    try {
      (void)parse_log_level(bad);
      ADD_FAILURE() << "no error for '" << bad << "'";
    } catch (const core::InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + bad + "'"), std::string::npos) << what;
      EXPECT_NE(what.find("trace, debug, info"), std::string::npos) << what;
    }
  }
}

TEST(LogTargetNames, KnownAndUnknown) {
  EXPECT_EQ(parse_log_target("auto"), LogTarget::Auto);
  EXPECT_EQ(parse_log_target("journal"), LogTarget::Journal);
  EXPECT_EQ(parse_log_target("stderr"), LogTarget::Stderr);
  EXPECT_EQ(parse_log_target("Journal"), LogTarget::Journal);
  try {
    (void)parse_log_target("syslog");
    FAIL() << "no error";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'syslog'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::settings
