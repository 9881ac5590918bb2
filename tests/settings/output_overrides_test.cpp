// The command line's --instance, --socket and --shm over the configuration's outputs: the
// instance's names, each replaced by an explicit option, checked by the configuration's own
// rules, and errors naming the option.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ipc/instance_name.hpp"
#include "settings/daemon_config_error.hpp"
#include "settings/embedded_default_config.hpp"
#include "settings/output_overrides.hpp"

namespace tofcomp::settings {
namespace {

std::string error_of(const std::string& instance, const std::string& socket,
                     const std::string& shm) {
  try {
    output_overrides(instance, socket, shm);
  } catch (const DaemonConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(OutputOverrides, NoneLeavesTheConfigurationAlone) {
  DaemonConfig config = embedded_default_config();
  const DaemonConfig before = config;
  apply_output_overrides(output_overrides("", "", ""), config);
  EXPECT_EQ(config.outputs.socket.path, before.outputs.socket.path);
  EXPECT_EQ(config.outputs.shm.name, before.outputs.shm.name);
}

TEST(OutputOverrides, AnInstanceNamesItsSocketAndRing) {
  DaemonConfig config = embedded_default_config();
  apply_output_overrides(output_overrides("left-2", "", ""), config);
  EXPECT_EQ(config.outputs.socket.path, "/run/tofcompd/left-2/tofcompd.sock");
  EXPECT_EQ(config.outputs.shm.name, "/tofcompd-left-2");
  EXPECT_EQ(ipc::instance_log_identity("left-2"), "tofcompd@left-2");
  // The rest of the outputs stay the file's.
  EXPECT_EQ(config.outputs.shm.slots, embedded_default_config().outputs.shm.slots);
}

TEST(OutputOverrides, SocketAndShmReplaceTheInstancesAndARelativeSocketIsMadeAbsolute) {
  DaemonConfig config = embedded_default_config();
  apply_output_overrides(output_overrides("left", "run/my.sock", "/mine"), config);
  EXPECT_EQ(config.outputs.socket.path, std::filesystem::current_path() / "run" / "my.sock");
  EXPECT_EQ(config.outputs.shm.name, "/mine");
  apply_output_overrides(output_overrides("right", "/tmp/right.sock", ""), config);
  EXPECT_EQ(config.outputs.socket.path, "/tmp/right.sock");
  EXPECT_EQ(config.outputs.shm.name, "/tofcompd-right");
}

TEST(OutputOverrides, ValuesBreakingTheRulesAreRefusedNamingTheOption) {
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

}  // namespace
}  // namespace tofcomp::settings
