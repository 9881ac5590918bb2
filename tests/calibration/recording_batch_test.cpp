// The fleet batch's edges without training (calibration/recording_batch.hpp): which files of a
// directory are recordings, the directories it refuses, and that recordings which cannot be read
// each keep their own error while every recording is started and finished once. The batch's
// results on recordings that train are checked end to end (tests/cli/calibrate_dir_test.sh).
#include "calibration/recording_batch.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>

#include "core/error.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::calibration {
namespace {

namespace fs = std::filesystem;

class RecordingBatch : public ::testing::Test {
 protected:
  void write(const std::string& name, const std::string& contents) const {
    std::ofstream(dir_ / name) << contents;
  }
  const test::TemporaryDirectory directory_{"tofcomp-batch"};
  const fs::path dir_ = directory_.path();
};

TEST_F(RecordingBatch, ListsTheCsvFilesOfTheDirectoryByName) {
  write("b.csv", "x");
  write("a.csv", "x");
  write("c.CSV.bak", "x");
  write("notes.txt", "x");
  fs::create_directories(dir_ / "sub.csv");
  fs::create_directories(dir_ / "deeper");
  write("deeper/d.csv", "x");
  const std::vector<fs::path> found = recordings_in(dir_);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].filename(), "a.csv");
  EXPECT_EQ(found[1].filename(), "b.csv");
}

TEST_F(RecordingBatch, RefusesADirectoryWithoutRecordingsOrMissing) {
  write("notes.txt", "x");
  try {
    recordings_in(dir_);
    FAIL() << "a directory without recordings was accepted";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(dir_.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no recording"), std::string::npos) << e.what();
  }
  EXPECT_THROW(recordings_in(dir_ / "missing"), core::InvalidInput);
  EXPECT_THROW(recordings_in(dir_ / "notes.txt"), core::InvalidInput);
}

TEST_F(RecordingBatch, RefusesMoreRecordingsThanItsLimit) {
  for (std::size_t i = 0; i <= kMaxBatchRecordings; ++i) {
    std::ofstream(dir_ / ("r" + std::to_string(i) + ".csv"));
  }
  try {
    recordings_in(dir_);
    FAIL() << "more than the limit accepted";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxBatchRecordings)), std::string::npos)
        << e.what();
  }
}

TEST_F(RecordingBatch, EachRecordingKeepsItsOwnErrorAndTheOthersGoOn) {
  write("empty.csv", "");
  write("garbage.csv", "not,a\nrecording\n");
  write("no-header.csv", "1,2,3\n4,5,6\n");
  const std::vector<fs::path> recordings = recordings_in(dir_);
  ASSERT_EQ(recordings.size(), 3u);
  BatchSettings settings;
  settings.jobs = 2;
  std::map<std::size_t, int> started, finished;
  std::map<std::size_t, RecordingOutcome> outcomes;
  calibrate_recordings(
      recordings, settings, [&](std::size_t i) { ++started[i]; },
      [&](std::size_t i, RecordingOutcome&& outcome) {
        ++finished[i];
        outcomes.emplace(i, std::move(outcome));
      });
  for (std::size_t i = 0; i < recordings.size(); ++i) {
    EXPECT_EQ(started[i], 1) << i;
    EXPECT_EQ(finished[i], 1) << i;
    const RecordingOutcome& o = outcomes.at(i);
    EXPECT_EQ(o.recording, recordings[i]);
    EXPECT_FALSE(o.calibrated());
    // The reader names the file in its error, so a user of the batch knows which one failed.
    EXPECT_NE(o.error.find(recordings[i].filename().string()), std::string::npos) << o.error;
    EXPECT_THROW(o.calibration(), core::Error);
  }
}

}  // namespace
}  // namespace tofcomp::calibration
