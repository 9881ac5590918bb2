// A writer thread publishing as fast as it can into a small ring while reader threads copy: every
// scan a reader gets is one the writer published, whole (each value is a function of the scan's
// sequence and the beam index, so a copy mixing two scans shows), in order, and the cursor
// accounts for every publish as read or lost. latest() may give up while the writer laps the
// ring (its documented error); once the writer stops it reads the newest scan whole.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>

#include "core/error.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::difference;
using testing::known_scan;
using testing::ScopedRingName;

constexpr std::uint64_t kMaxScans = 200000;
constexpr auto kMaxDuration = std::chrono::seconds(2);
// What RingReader::latest() says when the writer laps the ring faster than it can copy a scan.
constexpr const char* kLappedMessage = "laps the ring";

// Varying beam counts, so that a header copied from one scan and beams from another differ.
std::size_t beams_of(std::uint64_t sequence) {
  return 300 + sequence % 62;
}

struct CursorResult {
  std::uint64_t read = 0;
  std::uint64_t lost = 0;
  std::uint64_t torn = 0;
  std::uint64_t inconsistent = 0;
  std::uint64_t out_of_order = 0;
  std::string first_problem;
};

void check(const CompensatedScan& scan, std::uint64_t& inconsistent, std::string& first_problem) {
  const std::string d = difference(scan, known_scan(scan.sequence, beams_of(scan.sequence)));
  if (!d.empty()) {
    if (first_problem.empty()) first_problem = "scan " + std::to_string(scan.sequence) + ": " + d;
    ++inconsistent;
  }
}

TEST(RingConcurrency, EveryScanReadWhileTheWriterRacesIsWhole) {
  for (const std::uint32_t slots : {2u, 16u}) {
    const ScopedRingName name("race");
    RingWriter writer(name, slots, 361);
    RingReader cursor_reader(name);
    RingReader latest_reader(name);
    std::atomic<bool> writer_done{false};

    std::thread writer_thread([&] {
      const auto end = std::chrono::steady_clock::now() + kMaxDuration;
      for (std::uint64_t s = 0; s < kMaxScans; ++s) {
        writer.publish(known_scan(s, beams_of(s)));
        if ((s & 255) == 0 && std::chrono::steady_clock::now() > end) break;
      }
      writer_done.store(true, std::memory_order_release);
    });

    CursorResult cursor;
    std::thread cursor_thread([&] {
      std::uint64_t next_at_least = 0;
      const auto drain = [&] {
        const ReadBatch batch = cursor_reader.read_new();
        cursor.lost += batch.lost;
        cursor.torn += batch.torn_reads;
        for (const CompensatedScan& scan : batch.scans) {
          if (scan.sequence < next_at_least) ++cursor.out_of_order;
          next_at_least = scan.sequence + 1;
          check(scan, cursor.inconsistent, cursor.first_problem);
        }
        cursor.read += batch.scans.size();
        return !batch.scans.empty() || batch.lost != 0;
      };
      while (!writer_done.load(std::memory_order_acquire)) drain();
      while (drain()) {
      }
    });

    std::uint64_t latest_read = 0;
    std::uint64_t latest_lapped = 0;
    std::uint64_t latest_inconsistent = 0;
    std::uint64_t latest_backwards = 0;
    std::string latest_problem;
    std::thread latest_thread([&] {
      std::uint64_t newest = 0;
      while (!writer_done.load(std::memory_order_acquire)) {
        // A writer with no pause laps a ring of two slots in microseconds; when the reader's
        // thread is slower (another process has the core), latest() gives up with the error the
        // library documents. That is an answer, not a torn scan: counted, and the read goes on.
        std::optional<CompensatedScan> scan;
        try {
          scan = latest_reader.latest();
        } catch (const core::Error& e) {
          if (std::string(e.what()).find(kLappedMessage) == std::string::npos) throw;
          ++latest_lapped;
          continue;
        }
        if (!scan) continue;
        ++latest_read;
        if (scan->sequence < newest) ++latest_backwards;
        newest = scan->sequence;
        check(*scan, latest_inconsistent, latest_problem);
      }
    });

    writer_thread.join();
    cursor_thread.join();
    latest_thread.join();
    // With the writer stopped, the newest scan is there to be read, whole.
    const auto last = latest_reader.latest();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->sequence, writer.published() - 1);
    check(*last, latest_inconsistent, latest_problem);

    std::printf(
        "[ ring of %u slots ] published %llu; cursor read %llu, lost %llu (%llu torn); "
        "latest read %llu, %llu torn, lapped %llu times\n",
        slots, static_cast<unsigned long long>(writer.published()),
        static_cast<unsigned long long>(cursor.read), static_cast<unsigned long long>(cursor.lost),
        static_cast<unsigned long long>(cursor.torn), static_cast<unsigned long long>(latest_read),
        static_cast<unsigned long long>(latest_reader.counters().torn_reads),
        static_cast<unsigned long long>(latest_lapped));
    EXPECT_EQ(cursor.inconsistent, 0u) << cursor.first_problem;
    EXPECT_EQ(latest_inconsistent, 0u) << latest_problem;
    EXPECT_EQ(cursor.out_of_order, 0u);
    EXPECT_EQ(latest_backwards, 0u);
    EXPECT_EQ(cursor.read + cursor.lost, writer.published());
    EXPECT_GT(cursor.read, 0u);
    EXPECT_EQ(cursor_reader.counters().scans_read, cursor.read);
    EXPECT_EQ(cursor_reader.counters().lost, cursor.lost);
  }
}

}  // namespace
}  // namespace tofcomp::ipc::ring
