// A reader's cursor: it gets every scan published after it, in order, at most a ring's worth
// when it lags, and is told exactly how many it lost.
#include <gtest/gtest.h>

#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::difference;
using testing::known_scan;
using testing::ScopedRingName;

constexpr std::uint32_t kSlots = 8;
constexpr std::size_t kBeams = 5;

TEST(RingLag, ReaderThreeRingsBehindLosesTwoRings) {
  const ScopedRingName name("lag");
  RingWriter writer(name, kSlots, 16);
  RingReader reader(name);
  for (std::uint64_t s = 0; s < 3 * kSlots; ++s) writer.publish(known_scan(s, kBeams));

  const ReadBatch batch = reader.read_new();
  EXPECT_EQ(batch.lost, 2u * kSlots);
  ASSERT_EQ(batch.scans.size(), kSlots);
  for (std::size_t k = 0; k < kSlots; ++k) {
    EXPECT_EQ(difference(batch.scans[k], known_scan(2 * kSlots + k, kBeams)), "") << k;
  }
  EXPECT_EQ(reader.counters().lost, 2u * kSlots);
  EXPECT_EQ(reader.counters().scans_read, kSlots);
  EXPECT_EQ(reader.cursor(), 3u * kSlots);

  // Caught up: the next scans come without loss.
  writer.publish(known_scan(100, kBeams));
  writer.publish(known_scan(101, kBeams));
  const ReadBatch next = reader.read_new();
  EXPECT_EQ(next.lost, 0u);
  ASSERT_EQ(next.scans.size(), 2u);
  EXPECT_EQ(next.scans[0].sequence, 100u);
  EXPECT_EQ(next.scans[1].sequence, 101u);
  EXPECT_EQ(reader.counters().lost, 2u * kSlots);
}

TEST(RingLag, ExactlyOneRingBehindLosesNothing) {
  const ScopedRingName name("full");
  RingWriter writer(name, kSlots, 16);
  RingReader reader(name);
  for (std::uint64_t s = 0; s < kSlots; ++s) writer.publish(known_scan(s, kBeams));
  const ReadBatch batch = reader.read_new();
  EXPECT_EQ(batch.lost, 0u);
  ASSERT_EQ(batch.scans.size(), kSlots);
  EXPECT_EQ(batch.scans.front().sequence, 0u);
  EXPECT_EQ(batch.scans.back().sequence, kSlots - 1);
  writer.publish(known_scan(kSlots, kBeams));
  writer.publish(known_scan(kSlots + 1, kBeams));
  // One more than a ring behind: one lost.
  for (std::uint64_t s = kSlots + 2; s < 2 * kSlots + 3; ++s) writer.publish(known_scan(s, 1));
  const ReadBatch lagged = reader.read_new();
  EXPECT_EQ(lagged.lost, 3u);
  ASSERT_EQ(lagged.scans.size(), kSlots);
  EXPECT_EQ(lagged.scans.front().sequence, kSlots + 3);
}

TEST(RingLag, MaxScansSplitsABatchWithoutLoss) {
  const ScopedRingName name("split");
  RingWriter writer(name, kSlots, 16);
  RingReader reader(name);
  for (std::uint64_t s = 0; s < 5; ++s) writer.publish(known_scan(s, kBeams));
  const ReadBatch first = reader.read_new(2);
  ASSERT_EQ(first.scans.size(), 2u);
  EXPECT_EQ(first.scans[1].sequence, 1u);
  EXPECT_EQ(reader.cursor(), 2u);
  const ReadBatch rest = reader.read_new();
  ASSERT_EQ(rest.scans.size(), 3u);
  EXPECT_EQ(rest.scans[0].sequence, 2u);
  EXPECT_EQ(rest.lost, 0u);
  EXPECT_TRUE(reader.read_new().scans.empty());
}

TEST(RingLag, NewReaderStartsAtTheNextScanAndCanRewind) {
  const ScopedRingName name("rewind");
  RingWriter writer(name, kSlots, 16);
  for (std::uint64_t s = 0; s < 11; ++s) writer.publish(known_scan(s, kBeams));
  RingReader reader(name);
  EXPECT_EQ(reader.cursor(), 11u);
  EXPECT_TRUE(reader.read_new().scans.empty());
  EXPECT_EQ(reader.latest()->sequence, 10u);

  reader.rewind_to_oldest();
  EXPECT_EQ(reader.cursor(), 11u - kSlots);
  const ReadBatch batch = reader.read_new();
  EXPECT_EQ(batch.lost, 0u);
  ASSERT_EQ(batch.scans.size(), kSlots);
  EXPECT_EQ(batch.scans.front().sequence, 3u);
  EXPECT_EQ(batch.scans.back().sequence, 10u);
}

}  // namespace
}  // namespace tofcomp::ipc::ring
