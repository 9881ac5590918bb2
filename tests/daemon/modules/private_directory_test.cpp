// A user's own runtime folder is used only when it is that user's alone
// (daemon/private_directory.hpp): made 0700 when missing; a symlink, a folder others may write
// and another user's folder are refused, each named.
#include "daemon/private_directory.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"

namespace tofcomp::daemon {
namespace {

namespace fs = std::filesystem;

// The uid of nobody on Debian: an owner that is not the test's when it runs as root.
constexpr uid_t kNobody = 65534;

class PrivateDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = fs::temp_directory_path() / ("tofcomp-private-" + std::to_string(::getpid()));
    fs::remove_all(base_);
    fs::create_directories(base_);
  }
  void TearDown() override { fs::remove_all(base_); }

  // The message make_private_directory throws for `directory`, or "" when it accepts it.
  static std::string refusal(const fs::path& directory) {
    try {
      make_private_directory(directory);
      return "";
    } catch (const core::Error& e) {
      return e.what();
    }
  }
  fs::path base_;
};

TEST_F(PrivateDirectory, AMissingFolderIsMadeForItsUserAlone) {
  const fs::path folder = base_ / "run" / "tofcompd";
  EXPECT_EQ(refusal(folder), "");
  struct stat status {};
  ASSERT_EQ(::lstat(folder.c_str(), &status), 0);
  EXPECT_TRUE(S_ISDIR(status.st_mode));
  EXPECT_EQ(status.st_mode & 07777, 0700u);
  EXPECT_EQ(status.st_uid, ::geteuid());
  EXPECT_EQ(refusal(folder), "") << "an existing folder of its own is used again";
}

TEST_F(PrivateDirectory, ASymlinkInItsPlaceIsRefused) {
  fs::create_directories(base_ / "elsewhere");
  fs::create_directory_symlink(base_ / "elsewhere", base_ / "tofcompd");
  const std::string message = refusal(base_ / "tofcompd");
  EXPECT_NE(message.find("is not a directory"), std::string::npos) << message;
}

TEST_F(PrivateDirectory, AFolderOthersMayWriteIsRefused) {
  const fs::path folder = base_ / "tofcompd";
  fs::create_directory(folder);
  ASSERT_EQ(::chmod(folder.c_str(), 0777), 0);
  const std::string message = refusal(folder);
  EXPECT_NE(message.find("mode 0777"), std::string::npos) << message;
}

TEST_F(PrivateDirectory, AnotherUsersFolderIsRefused) {
  if (::geteuid() != 0) GTEST_SKIP() << "giving a folder to another user needs root";
  const fs::path folder = base_ / "tofcompd";
  fs::create_directory(folder);
  ASSERT_EQ(::chmod(folder.c_str(), 0700), 0);
  ASSERT_EQ(::chown(folder.c_str(), kNobody, kNobody), 0);
  const std::string message = refusal(folder);
  EXPECT_NE(message.find("belongs to uid 65534"), std::string::npos) << message;
}

}  // namespace
}  // namespace tofcomp::daemon
