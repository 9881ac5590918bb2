// Opening files others name (io/checked_file.hpp) on real files of each kind: a regular file is
// read whole; a FIFO (which would block a plain open), a device, a directory, a file over the cap
// are refused naming what they are, without blocking; in a directory, only a file directly in it
// and not a link is taken, so that no "..", absolute path or link leads out. And the temporaries
// an interrupted atomic write leaves beside a file (io/atomic_file.hpp) are found and removed,
// nothing else.
#include "io/checked_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::io {
namespace {

namespace fs = std::filesystem;

class CheckedFileTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  // The message of the refusal of `open`, or "" when it opened.
  template <class Open>
  std::string refusal(Open open) {
    try {
      open();
    } catch (const core::InvalidInput& e) {
      return e.what();
    }
    return "";
  }
  const test::TemporaryDirectory directory_{"tofcomp-checked"};
  const fs::path dir_ = directory_.path();
};

TEST_F(CheckedFileTest, ARegularFileIsReadWhole) {
  const fs::path file = write("a.csv", "time_s\n0\n");
  const CheckedFile checked = open_checked_file(file, 100, "recording", "cap");
  EXPECT_EQ(checked.size(), 9u);
  EXPECT_EQ(read_checked_file(checked, 100, "recording", "cap"), "time_s\n0\n");
}

TEST_F(CheckedFileTest, AFifoIsRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  EXPECT_EQ(refusal([&] { open_checked_file(dir_ / "fifo", 100, "recording", "cap"); }),
            "recording " + (dir_ / "fifo").string() +
                ": a FIFO (named pipe), not a regular file; it is not read");
}

TEST_F(CheckedFileTest, DevicesAndDirectoriesAreRefused) {
  EXPECT_EQ(refusal([&] { open_checked_file("/dev/zero", 100, "recording", "cap"); }),
            "recording /dev/zero: a character device, not a regular file; it is not read");
  EXPECT_EQ(refusal([&] { open_checked_file(dir_, 100, "recording", "cap"); }),
            "recording " + dir_.string() + ": a directory, not a regular file; it is not read");
}

TEST_F(CheckedFileTest, AFileOverTheCapIsRefusedBeforeItIsRead) {
  const fs::path file = write("big.csv", std::string(101, 'x'));
  EXPECT_EQ(
      refusal([&] { open_checked_file(file, 100, "recording", "the cap"); }),
      "recording " + file.string() + ": 101 bytes, more than the 100 of the cap; it is not read");
}

TEST_F(CheckedFileTest, AMissingFileIsNamed) {
  EXPECT_EQ(refusal([&] { open_checked_file(dir_ / "gone.csv", 100, "recording", "cap"); }),
            "recording " + (dir_ / "gone.csv").string() + ": does not exist");
}

// A name from outside cannot cut or split the message that carries it (issue 53: a "\n" in a
// file name reached the log raw): its control characters are escaped.
TEST_F(CheckedFileTest, ControlCharactersOfANameAreEscapedInTheMessage) {
  constexpr char kName[] = "a\nforged line\x1b[2J\0b.csv";
  const fs::path named = dir_ / std::string(kName, sizeof kName - 1);
  EXPECT_EQ(refusal([&] { open_checked_file(named, 100, "recording", "cap"); }),
            "recording " + dir_.string() + "/a\\nforged line\\x1B[2J\\x00b.csv: does not exist");
}

TEST_F(CheckedFileTest, InADirectoryOnlyAFileDirectlyInItAndNoLink) {
  write("in.csv", "time_s\n");
  fs::create_directory(dir_ / "sub");
  write("sub/deeper.csv", "time_s\n");
  fs::create_symlink("/etc/hostname", dir_ / "out.csv");
  fs::create_symlink(dir_ / "in.csv", dir_ / "alias.csv");
  const auto open_in = [&](const fs::path& named) {
    return open_checked_file_in(dir_, named, 100, "recording", "cap", "the directory setting");
  };
  EXPECT_EQ(open_in("in.csv").size(), 7u);
  EXPECT_EQ(open_in(dir_ / "in.csv").size(), 7u);
  const std::string outside = "not a file directly in " + dir_.string() +
                              " (the directory setting), the one directory recordings may come "
                              "from";
  for (const fs::path& named : {fs::path("sub/deeper.csv"), fs::path("../x.csv"),
                               fs::path("/dev/zero"), fs::path("/etc/hostname"), fs::path("")}) {
    EXPECT_NE(refusal([&] { open_in(named); }).find(outside), std::string::npos) << named;
  }
  // A link, wherever it points, is not followed.
  EXPECT_NE(refusal([&] { open_in("out.csv"); }).find("out.csv: a symbolic link"),
            std::string::npos);
  EXPECT_NE(refusal([&] { open_in("alias.csv"); }).find("alias.csv: a symbolic link"),
            std::string::npos);
}

TEST_F(CheckedFileTest, StaleTemporariesOfAnInterruptedWriteAreRemovedNothingElse) {
  const fs::path target = dir_ / "calibration.yaml";
  write("calibration.yaml", "kept\n");
  const fs::path stale = write(".calibration.yaml.k3Jq9Z", "torn");
  const fs::path other_file = write(".other.yaml.k3Jq9Z", "another file's");
  const fs::path not_random = write(".calibration.yaml.k3-q9Z", "not mkstemp's");
  const fs::path too_long = write(".calibration.yaml.k3Jq9Zx", "not mkstemp's");
  fs::create_directory(dir_ / ".calibration.yaml.AAAAAA");
  const std::vector<fs::path> removed = remove_stale_temporaries(target);
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0], stale);
  EXPECT_FALSE(fs::exists(stale));
  for (const fs::path& p :
       {target, other_file, not_random, too_long, dir_ / ".calibration.yaml.AAAAAA"}) {
    EXPECT_TRUE(fs::exists(p)) << p;
  }
}

}  // namespace
}  // namespace tofcomp::io
