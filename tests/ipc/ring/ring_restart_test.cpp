// Writer restarts: a reader follows a ring re-created under the same name (after a clean close
// or a crash of its writer) and says so; a writer replaces a ring left by a dead writer but not
// one whose writer still runs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/error.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::difference;
using testing::known_scan;
using testing::run_in_child;
using testing::ScopedRingName;

TEST(RingRestart, ReaderFollowsARingRecreatedAfterACleanClose) {
  const ScopedRingName name("clean");
  auto first = std::make_unique<RingWriter>(name, 4, 8);
  const std::uint64_t first_generation = first->generation();
  RingReader reader(name);
  for (std::uint64_t s = 0; s < 3; ++s) first->publish(known_scan(s, 2));
  EXPECT_EQ(reader.read_new().scans.size(), 3u);
  first.reset();

  // Closed and gone: nothing new, no restart yet.
  const ReadBatch idle = reader.read_new();
  EXPECT_TRUE(idle.scans.empty());
  EXPECT_FALSE(idle.writer_restarted);
  EXPECT_TRUE(reader.info().writer_closed);
  EXPECT_FALSE(reader.writer_running());

  RingWriter second(name, 6, 8);
  EXPECT_NE(second.generation(), first_generation);
  second.publish(known_scan(0, 8));
  second.publish(known_scan(1, 8));
  const ReadBatch after = reader.read_new();
  EXPECT_TRUE(after.writer_restarted);
  EXPECT_EQ(after.lost, 0u);
  ASSERT_EQ(after.scans.size(), 2u);
  EXPECT_EQ(difference(after.scans[0], known_scan(0, 8)), "");
  EXPECT_EQ(difference(after.scans[1], known_scan(1, 8)), "");
  EXPECT_EQ(reader.info().generation, second.generation());
  EXPECT_EQ(reader.info().slot_count, 6u);
  EXPECT_EQ(reader.counters().writer_restarts, 1u);
  EXPECT_TRUE(reader.writer_running());
  EXPECT_FALSE(reader.read_new().writer_restarted);
}

TEST(RingRestart, CrashedWritersRingIsReplacedAndTheReaderFollows) {
  const ScopedRingName name("crash");
  // The child publishes five scans and dies without closing its ring.
  ASSERT_EQ(run_in_child([&] {
              try {
                auto* leaked = new RingWriter(name, 8, 4);
                for (std::uint64_t s = 0; s < 5; ++s) leaked->publish(known_scan(s, 4));
                return 0;
              } catch (...) {
                return 1;
              }
            }),
            0);

  RingReader reader(name);
  EXPECT_FALSE(reader.info().writer_closed);
  EXPECT_FALSE(reader.writer_running());  // its process is gone
  const std::uint64_t crashed_generation = reader.info().generation;
  reader.rewind_to_oldest();
  const ReadBatch left = reader.read_new();
  ASSERT_EQ(left.scans.size(), 5u);
  EXPECT_EQ(difference(left.scans[4], known_scan(4, 4)), "");

  RingWriter restarted(name, 8, 4);
  EXPECT_GT(restarted.generation(), crashed_generation);
  restarted.publish(known_scan(100, 4));
  const auto latest = reader.latest();  // follows the restart too
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(difference(*latest, known_scan(100, 4)), "");
  EXPECT_EQ(reader.counters().writer_restarts, 1u);
  restarted.publish(known_scan(101, 4));
  const ReadBatch batch = reader.read_new();
  ASSERT_EQ(batch.scans.size(), 2u);
  EXPECT_EQ(batch.scans[0].sequence, 100u);
  EXPECT_EQ(batch.scans[1].sequence, 101u);
}

TEST(RingRestart, RingOfARunningWriterIsNotReplaced) {
  const ScopedRingName name("live");
  int ready[2];
  int release[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(release), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    int code = 0;
    try {
      RingWriter writer(name, 4, 4);
      writer.publish(known_scan(9, 4));
      char byte = 'r';
      if (::write(ready[1], &byte, 1) != 1) code = 2;
      if (::read(release[0], &byte, 1) != 1) code = 3;  // until the parent is done
    } catch (...) {
      code = 1;
    }
    ::_exit(code);
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  std::string message;
  try {
    RingWriter intruder(name, 4, 4);
  } catch (const core::Error& e) {
    message = e.what();
  }
  ASSERT_EQ(::write(release[1], &byte, 1), 1);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_NE(message.find("shm object '" + name.str() + "' is in use by a running writer (pid " +
                         std::to_string(child) + ", which holds its lock)"),
            std::string::npos)
      << message;
  for (int fd : {ready[0], ready[1], release[0], release[1]}) ::close(fd);
  EXPECT_THROW(RingReader{name.str()}, core::Error);  // the child removed its ring on exit
}

TEST(RingRestart, SecondWriterOfTheSameNameInOneProcessIsAnError) {
  const ScopedRingName name("twice");
  RingWriter writer(name, 4, 4);
  EXPECT_THROW(RingWriter(name, 4, 4), core::Error);
  writer.publish(known_scan(1, 4));
  RingReader reader(name);
  EXPECT_EQ(reader.latest()->sequence, 1u);
}

}  // namespace
}  // namespace tofcomp::ipc::ring
