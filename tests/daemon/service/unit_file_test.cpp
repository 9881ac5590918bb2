// The shipped unit and sysusers files, checked by systemd's own offline tools:
// `systemd-analyze verify` on the unit (with ExecStart pointed at /bin/true, since
// /usr/bin/tofcompd is not installed on a build machine) and `systemd-sysusers --root` on the
// sysusers file. Broken copies show that the checks catch real errors. Neither needs root nor a
// running systemd.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "ipc/socket/protocol_constants.hpp"
#include "ipc/socket/server_defaults.hpp"
#include "tests/support/file_text.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::daemon::service {
namespace {

namespace fs = std::filesystem;

const fs::path kSystemdDir = TOFCOMP_SYSTEMD_DIR;
const fs::path kUnitDir = TOFCOMP_UNIT_DIR;
constexpr const char* kShippedExecStart =
    "ExecStart=/usr/bin/tofcompd --config /etc/tofcompd/tofcompd.yaml";
constexpr const char* kInstanceExecStart =
    "ExecStart=/usr/bin/tofcompd --config /etc/tofcompd/%i.yaml --instance %i";

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

CommandResult run(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string quoted(const fs::path& path) {
  return "'" + path.string() + "'";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the text";
  if (at == std::string::npos) return text;
  return text.replace(at, from.size(), to);
}

class SystemdFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    unit_ = testing::file_text(kUnitDir / "tofcompd.service");
    ASSERT_FALSE(unit_.empty()) << kUnitDir / "tofcompd.service";
    instance_unit_ = testing::file_text(kUnitDir / "tofcompd@.service");
    ASSERT_FALSE(instance_unit_.empty()) << kUnitDir / "tofcompd@.service";
    socket_unit_ = testing::file_text(kUnitDir / "tofcompd.socket");
    ASSERT_FALSE(socket_unit_.empty()) << kUnitDir / "tofcompd.socket";
  }

  // The unit as shipped but for the executable, which a build machine does not have installed.
  std::string checkable_unit() const {
    return replaced(unit_, "ExecStart=/usr/bin/tofcompd ", "ExecStart=/bin/true ");
  }

  // `systemd-analyze verify` passes a unit only when it exits 0 and says nothing: it reports
  // unknown keys and unparsable values as warnings with exit status 0.
  CommandResult verify(const std::string& text,
                       const std::string& name = "tofcompd.service") const {
    const fs::path file = directory_ / name;
    std::ofstream(file) << text;
    return run("systemd-analyze verify --man=no " + quoted(file));
  }
  static bool passes(const CommandResult& r) { return r.exit_code == 0 && r.output.empty(); }

  test::TemporaryDirectory directory_;
  std::string unit_;
  std::string instance_unit_;  // tofcompd@.service
  std::string socket_unit_;    // tofcompd.socket
};

// The value of the one line KEY=... of a unit; fails the test when there is not exactly one.
std::string value_of(const std::string& unit, const std::string& key) {
  const std::regex line("\n" + key + "=([^\n]*)\n");
  const auto count =
      std::distance(std::sregex_iterator(unit.begin(), unit.end(), line), std::sregex_iterator());
  EXPECT_EQ(count, 1) << key << " in\n" << unit;
  std::smatch m;
  return std::regex_search(unit, m, line) ? m[1].str() : std::string();
}

TEST_F(SystemdFilesTest, ToolsArePresent) {
  // tools/setup.sh installs the systemd package; without it the checks below cannot run.
  EXPECT_EQ(run("systemd-analyze --version").exit_code, 0) << "install the systemd package";
  EXPECT_EQ(run("systemd-sysusers --version").exit_code, 0) << "install the systemd package";
}

TEST_F(SystemdFilesTest, ShippedUnitStartsTheInstalledDaemonWithItsConfig) {
  std::istringstream lines(unit_);
  std::string line;
  int exec_starts = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("ExecStart=", 0) == 0) {
      ++exec_starts;
      EXPECT_EQ(line, kShippedExecStart);
    }
  }
  EXPECT_EQ(exec_starts, 1);
}

TEST_F(SystemdFilesTest, UnitVerifiesCleanly) {
  const CommandResult r = verify(checkable_unit());
  EXPECT_TRUE(passes(r)) << "exit " << r.exit_code << ":\n" << r.output;
}

// tofcompd.socket: verified beside the service it starts; it listens where the daemon serves as
// root, with the permissions and owners the daemon gives a socket it makes itself.
TEST_F(SystemdFilesTest, SocketUnitOpensTheSocketTheDaemonServes) {
  std::ofstream(directory_ / "tofcompd.service") << checkable_unit();
  const CommandResult r = verify(socket_unit_, "tofcompd.socket");
  EXPECT_TRUE(passes(r)) << "exit " << r.exit_code << ":\n" << r.output;

  EXPECT_EQ(value_of(socket_unit_, "ListenStream"), ipc::socket::kDefaultSocketPath);
  EXPECT_EQ(std::stoul(value_of(socket_unit_, "SocketMode"), nullptr, 8),
            ipc::socket::kDefaultSocketMode);
  EXPECT_EQ(value_of(socket_unit_, "SocketUser"), value_of(unit_, "User"));
  EXPECT_EQ(value_of(socket_unit_, "SocketGroup"), value_of(unit_, "Group"));
  EXPECT_EQ(value_of(socket_unit_, "Accept"), "no");
  // The socket's directory is the service's runtime directory, which must outlive a stop.
  EXPECT_EQ(fs::path(ipc::socket::kDefaultSocketPath).parent_path(),
            fs::path("/run") / value_of(unit_, "RuntimeDirectory"));
  EXPECT_EQ(value_of(unit_, "RuntimeDirectoryPreserve"), "yes");
}

// tofcompd@.service: instance NAME reads /etc/tofcompd/NAME.yaml and publishes as --instance NAME
// says; its runtime and state directories are its own; otherwise it is the same unit.
TEST_F(SystemdFilesTest, InstanceUnitNamesItsConfigSocketAndStateByTheInstance) {
  EXPECT_NE(instance_unit_.find("\n" + std::string(kInstanceExecStart) + "\n"), std::string::npos)
      << instance_unit_;
  EXPECT_NE(instance_unit_.find("\nRuntimeDirectory=tofcompd/%i\n"), std::string::npos);
  EXPECT_NE(instance_unit_.find("\nStateDirectory=tofcompd/%i\n"), std::string::npos);
  std::string as_plain = instance_unit_;
  as_plain = replaced(as_plain, kInstanceExecStart, kShippedExecStart);
  as_plain = replaced(as_plain, "RuntimeDirectory=tofcompd/%i", "RuntimeDirectory=tofcompd");
  as_plain = replaced(as_plain, "StateDirectory=tofcompd/%i", "StateDirectory=tofcompd");
  as_plain = replaced(as_plain, " (instance %i)", "");
  EXPECT_EQ(as_plain, unit_);
  const CommandResult r =
      verify(replaced(instance_unit_, "ExecStart=/usr/bin/tofcompd ", "ExecStart=/bin/true "),
             "tofcompd@left.service");
  EXPECT_TRUE(passes(r)) << "exit " << r.exit_code << ":\n" << r.output;
}

TEST_F(SystemdFilesTest, VerifyCatchesAMissingExecutable) {
  // The unit as shipped names /usr/bin/tofcompd; a name that exists nowhere fails for certain.
  const CommandResult r =
      verify(replaced(unit_, "ExecStart=/usr/bin/tofcompd ", "ExecStart=/nonexistent/tofcompd "));
  EXPECT_FALSE(passes(r));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/nonexistent/tofcompd"), std::string::npos) << r.output;
}

TEST_F(SystemdFilesTest, VerifyCatchesABadValue) {
  const CommandResult r = verify(replaced(checkable_unit(), "Type=notify\n", "Type=notfiy\n"));
  EXPECT_FALSE(passes(r));
  EXPECT_NE(r.output.find("notfiy"), std::string::npos) << r.output;
}

TEST_F(SystemdFilesTest, VerifyCatchesAMisspelledKey) {
  const CommandResult r =
      verify(replaced(checkable_unit(), "ProtectHome=yes\n", "ProtectHomes=yes\n"));
  EXPECT_FALSE(passes(r));
  EXPECT_NE(r.output.find("ProtectHomes"), std::string::npos) << r.output;
}

// `systemd-analyze security --offline=yes` rates the unit's exposure from 0 (locked down) to 10;
// the hardening documented in docs/deployment.md keeps it at 2 or below, and a unit without any
// scores far above, so a lost protection shows here.
double exposure(const fs::path& unit_file) {
  const CommandResult r = run("systemd-analyze security --offline=yes " + quoted(unit_file));
  std::smatch m;
  if (r.exit_code != 0 ||
      !std::regex_search(r.output, m, std::regex("Overall exposure level for \\S+: ([0-9.]+)"))) {
    ADD_FAILURE() << "no exposure level, exit " << r.exit_code << ":\n" << r.output;
    return 10.0;
  }
  return std::stod(m[1]);
}

TEST_F(SystemdFilesTest, HardeningKeepsTheExposureLow) {
  const fs::path file = directory_ / "tofcompd.service";
  std::ofstream(file) << checkable_unit();
  EXPECT_LE(exposure(file), 2.0);

  std::ofstream(file, std::ios::trunc) << "[Service]\nType=notify\nExecStart=/bin/true\n";
  EXPECT_GT(exposure(file), 5.0);
}

// systemd-sysusers applied to an empty root that has only Debian's dialout group: the user the
// unit runs as appears, in every group the unit's SupplementaryGroups= names.
TEST_F(SystemdFilesTest, SysusersCreatesTheUserInTheUnitsGroups) {
  const fs::path root = directory_ / "root";
  fs::create_directories(root / "etc");
  std::ofstream(root / "etc" / "passwd") << "root:x:0:0:root:/root:/bin/sh\n";
  std::ofstream(root / "etc" / "group") << "root:x:0:\ndialout:x:20:\n";
  const CommandResult r = run("systemd-sysusers --root=" + quoted(root) + " " +
                              quoted(kSystemdDir / "tofcompd.sysusers"));
  ASSERT_EQ(r.exit_code, 0) << r.output;

  std::smatch m;
  ASSERT_TRUE(std::regex_search(unit_, m, std::regex("\nUser=(\\S+)\n"))) << "no User=";
  const std::string user = m[1];
  ASSERT_TRUE(std::regex_search(unit_, m, std::regex("\nGroup=(\\S+)\n"))) << "no Group=";
  const std::string group = m[1];
  ASSERT_TRUE(std::regex_search(unit_, m, std::regex("\nSupplementaryGroups=([^\n]+)\n")));
  const std::string supplementary = m[1];

  const std::string passwd = testing::file_text(root / "etc" / "passwd");
  const std::string groups = testing::file_text(root / "etc" / "group");
  ASSERT_TRUE(std::regex_search(passwd, m, std::regex("\n" + user + ":x:(\\d+):(\\d+):")))
      << passwd;
  const std::string gid = m[2];
  EXPECT_NE(groups.find("\n" + group + ":x:" + gid + ":"), std::string::npos) << groups;
  // Debian's dialout keeps its GID; missing groups are created; the user is in each.
  EXPECT_NE(groups.find("\ndialout:x:20:" + user + "\n"), std::string::npos) << groups;
  std::istringstream names(supplementary);
  std::string name;
  int count = 0;
  while (names >> name) {
    ++count;
    EXPECT_TRUE(std::regex_search(groups, std::regex("\n" + name + ":x:\\d+:" + user + "\n")))
        << name << " missing or without " << user << ":\n"
        << groups;
  }
  EXPECT_EQ(count, 3) << supplementary;
}

TEST_F(SystemdFilesTest, SysusersRejectsABrokenFile) {
  const fs::path root = directory_ / "root";
  fs::create_directories(root / "etc");
  const fs::path broken = directory_ / "broken.conf";
  std::ofstream(broken) << replaced(testing::file_text(kSystemdDir / "tofcompd.sysusers"),
                                    "m tofcompd dialout", "m tofcompd");
  const CommandResult r = run("systemd-sysusers --root=" + quoted(root) + " " + quoted(broken));
  EXPECT_NE(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace tofcomp::daemon::service
