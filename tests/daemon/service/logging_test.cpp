// configure_logging and its parts: systemd's JOURNAL_STREAM rule, and
// what reaches stderr.
#include "daemon/service/logging.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "tests/daemon/service/environment_guard.hpp"
#include "tests/support/file_text.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::daemon::service {
namespace {

namespace fs = std::filesystem;

std::string device_inode_of(int fd) {
  struct stat st {};
  EXPECT_EQ(::fstat(fd, &st), 0);
  return std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
}

// Points the process's stderr (fd 2) at a file for the guard's lifetime.
class StderrToFile {
 public:
  explicit StderrToFile(const fs::path& file) : file_(file) {
    std::fflush(stderr);
    saved_ = ::dup(STDERR_FILENO);
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    EXPECT_GE(fd, 0) << file;
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
  }
  StderrToFile(const StderrToFile&) = delete;
  StderrToFile& operator=(const StderrToFile&) = delete;
  ~StderrToFile() {
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
  }

 private:
  fs::path file_;
  int saved_ = -1;
};

TEST(JournalStreamRule, MatchesOnlyTheStreamsOwnDeviceAndInode) {
  const test::TemporaryDirectory directory;
  const fs::path file = directory / "journal_stream_rule.txt";
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  ASSERT_GE(fd, 0);
  struct stat st {};
  ASSERT_EQ(::fstat(fd, &st), 0);
  const std::string device = std::to_string(st.st_dev);
  const std::string inode = std::to_string(st.st_ino);

  EXPECT_TRUE(stream_is_journal((device + ":" + inode).c_str(), fd));
  EXPECT_FALSE(stream_is_journal((device + ":" + std::to_string(st.st_ino + 1)).c_str(), fd));
  EXPECT_FALSE(stream_is_journal((std::to_string(st.st_dev + 1) + ":" + inode).c_str(), fd));
  EXPECT_FALSE(stream_is_journal(nullptr, fd));
  for (const std::string& bad : std::vector<std::string>{
           "", ":", device + ":", ":" + inode, device + inode, device + ":" + inode + ":1",
           device + ":" + inode + " ", "-" + device + ":" + inode, "0x1:0x2"}) {
    EXPECT_FALSE(stream_is_journal(bad.c_str(), fd)) << "'" << bad << "'";
  }
  ::close(fd);
  // A descriptor that is not open matches nothing.
  EXPECT_FALSE(stream_is_journal((device + ":" + inode).c_str(), fd));
}

TEST(JournalStreamRule, AutoFollowsStderr) {
  test_support::EnvironmentGuard environment;
  const test::TemporaryDirectory directory;
  const fs::path file = directory / "auto_stderr.txt";
  StderrToFile redirect(file);
  const std::string ours = device_inode_of(STDERR_FILENO);

  environment.set("JOURNAL_STREAM", ours);
  EXPECT_EQ(resolve_log_target(LogTarget::Auto), LogTarget::Journal);
  EXPECT_EQ(resolve_log_target(LogTarget::Stderr), LogTarget::Stderr);

  // Inherited from a parent whose stderr went to the journal, but ours goes elsewhere now.
  environment.set("JOURNAL_STREAM", ours + "1");
  EXPECT_EQ(resolve_log_target(LogTarget::Auto), LogTarget::Stderr);
  EXPECT_EQ(resolve_log_target(LogTarget::Journal), LogTarget::Journal);

  environment.unset("JOURNAL_STREAM");
  EXPECT_EQ(resolve_log_target(LogTarget::Auto), LogTarget::Stderr);
}

TEST(ConfigureLogging, StderrGetsMessagesAtOrAboveTheLevel) {
  test_support::EnvironmentGuard environment;
  environment.unset("JOURNAL_STREAM");
  const test::TemporaryDirectory directory;
  const fs::path file = directory / "configure_logging_stderr.txt";
  {
    StderrToFile redirect(file);
    EXPECT_EQ(configure_logging(LogTarget::Auto, spdlog::level::info), LogTarget::Stderr);
    spdlog::debug("a debug line that the info level hides");
    spdlog::info("calibration loaded from {}", "/etc/tofcompd/calibration.yaml");
    spdlog::warn("sensor silent for {} s", 3);
    spdlog::default_logger()->flush();
  }
  const std::string text = testing::file_text(file);
  EXPECT_EQ(text.find("debug line"), std::string::npos) << text;
  EXPECT_NE(text.find(" info calibration loaded from /etc/tofcompd/calibration.yaml\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(" warning sensor silent for 3 s\n"), std::string::npos) << text;
  EXPECT_EQ(spdlog::default_logger()->name(), "tofcompd");
}

TEST(ConfigureLogging, JournalTargetUsesTheJournalSink) {
  EXPECT_EQ(configure_logging(LogTarget::Journal, spdlog::level::debug), LogTarget::Journal);
  const auto logger = spdlog::default_logger();
  ASSERT_EQ(logger->sinks().size(), 1u);
  EXPECT_NE(std::dynamic_pointer_cast<spdlog::sinks::systemd_sink_mt>(logger->sinks().front()),
            nullptr);
  EXPECT_EQ(logger->level(), spdlog::level::debug);
}

}  // namespace
}  // namespace tofcomp::daemon::service
