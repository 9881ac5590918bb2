// Readers in another process: a forked child opens the ring by name and reads, in order and
// unchanged, every scan the parent publishes after the fork.
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>

#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::difference;
using testing::known_scan;
using testing::ScopedRingName;

constexpr std::uint64_t kScans = 50;
constexpr std::uint32_t kSlotsForEveryScan = 64;  // holds them all: a late child loses none

// Exit codes of the child, so that a failure says what went wrong.
enum ChildResult {
  kAllRead = 0,
  kOpenFailed = 10,
  kTimedOut = 11,
  kWrongScan = 12,
  kLost = 13,
  kOutOfOrder = 14,
};

int read_in_child(const std::string& name) {
  try {
    RingReader reader(name);
    reader.rewind_to_oldest();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    std::uint64_t next = 0;
    while (next < kScans) {
      if (std::chrono::steady_clock::now() > deadline) return kTimedOut;
      const ReadBatch batch = reader.read_new();
      if (batch.lost != 0) return kLost;
      for (const CompensatedScan& scan : batch.scans) {
        if (scan.sequence != next) return kOutOfOrder;
        if (!difference(scan, known_scan(next, 361)).empty()) return kWrongScan;
        ++next;
      }
      if (batch.scans.empty()) ::sched_yield();
    }
    return kAllRead;
  } catch (...) {
    return kOpenFailed;
  }
}

TEST(RingProcess, ForkedChildReadsWhatTheParentWrites) {
  const ScopedRingName name("fork");
  RingWriter writer(name, kSlotsForEveryScan, 361);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(read_in_child(name));
  for (std::uint64_t s = 0; s < kScans; ++s) {
    writer.publish(known_scan(s, 361));
    ::sched_yield();
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), kAllRead);
}

}  // namespace
}  // namespace tofcomp::ipc::ring
