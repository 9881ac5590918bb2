// The command line's --instance, --socket and --shm over the configuration's outputs (the
// instance's names, each replaced by an explicit option, checked by the configuration's own
// rules, and errors naming the option), and -d and --log-level over its log section.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ipc/instance_name.hpp"
#include "settings/command_line_overrides.hpp"
#include "settings/daemon_config_error.hpp"
#include "settings/embedded_default_config.hpp"

namespace tofcomp::settings {
namespace {

std::string error_of(const std::string& instance, const std::string& socket,
                     const std::string& shm) {
  try {
    command_line_overrides(instance, socket, shm);
  } catch (const DaemonConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(CommandLineOverrides, NoneLeavesTheConfigurationAlone) {
  DaemonConfig config = embedded_default_config();
  const DaemonConfig before = config;
  apply_command_line_overrides(command_line_overrides("", "", ""), config);
  EXPECT_EQ(config.outputs.socket.path, before.outputs.socket.path);
  EXPECT_EQ(config.outputs.shm.name, before.outputs.shm.name);
}

TEST(CommandLineOverrides, AnInstanceNamesItsSocketAndRing) {
  DaemonConfig config = embedded_default_config();
  apply_command_line_overrides(command_line_overrides("left-2", "", ""), config);
  EXPECT_EQ(config.outputs.socket.path, "/run/tofcompd/left-2/tofcompd.sock");
  EXPECT_EQ(config.outputs.shm.name, "/tofcompd-left-2");
  EXPECT_EQ(ipc::instance_log_identity("left-2"), "tofcompd@left-2");
  // The rest of the outputs stay the file's.
  EXPECT_EQ(config.outputs.shm.slots, embedded_default_config().outputs.shm.slots);
}

TEST(CommandLineOverrides, SocketAndShmReplaceTheInstancesAndARelativeSocketIsMadeAbsolute) {
  DaemonConfig config = embedded_default_config();
  apply_command_line_overrides(command_line_overrides("left", "run/my.sock", "/mine"), config);
  EXPECT_EQ(config.outputs.socket.path, std::filesystem::current_path() / "run" / "my.sock");
  EXPECT_EQ(config.outputs.shm.name, "/mine");
  apply_command_line_overrides(command_line_overrides("right", "/tmp/right.sock", ""), config);
  EXPECT_EQ(config.outputs.socket.path, "/tmp/right.sock");
  EXPECT_EQ(config.outputs.shm.name, "/tofcompd-right");
}

TEST(CommandLineOverrides, ValuesBreakingTheRulesAreRefusedNamingTheOption) {
  EXPECT_EQ(error_of("../etc", "", ""),
            "--instance: instance name '../etc': must be 1 to 64 letters, digits, '-' and '_', "
            "starting with a letter or a digit");
  EXPECT_NE(error_of("-x", "", "").find("--instance: instance name '-x'"), std::string::npos);
  EXPECT_NE(error_of(std::string(ipc::kMaxInstanceNameBytes + 1, 'a'), "", "").find("--instance"),
            std::string::npos);
  EXPECT_EQ(error_of(std::string(ipc::kMaxInstanceNameBytes, 'a'), "", ""), "");
  const std::string long_socket = "/tmp/" + std::string(110, 's');
  EXPECT_EQ(error_of("", long_socket, ""),
            "--socket " + long_socket +
                ": is 115 bytes long once resolved; a Unix socket path has at most 107");
  EXPECT_EQ(error_of("", "", "tofcompd"),
            "--shm: must be a shared-memory name like \"/tofcompd\" (one leading /, no other, at "
            "most 255 characters after it), not \"tofcompd\"");
  EXPECT_NE(error_of("", "", "/a/b").find("--shm"), std::string::npos);
}

TEST(CommandLineOverrides, StderrAndALevelReplaceTheLogSection) {
  DaemonConfig config = embedded_default_config();
  config.log = {spdlog::level::warn, LogTarget::Journal};  // as a file's log section sets them
  CommandLineOverrides none = command_line_overrides("", "", "");
  add_log_overrides(false, "", none);
  apply_command_line_overrides(none, config);
  EXPECT_EQ(config.log.target, LogTarget::Journal);
  EXPECT_EQ(config.log.level, spdlog::level::warn);

  CommandLineOverrides both = command_line_overrides("", "", "");
  add_log_overrides(true, "DEBUG", both);
  apply_command_line_overrides(both, config);
  EXPECT_EQ(config.log.target, LogTarget::Stderr);
  EXPECT_EQ(config.log.level, spdlog::level::debug);

  CommandLineOverrides bad;
  try {
    add_log_overrides(false, "loud", bad);
    ADD_FAILURE() << "--log-level loud was taken";
  } catch (const DaemonConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--log-level: ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("loud"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::settings
