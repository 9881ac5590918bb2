// 100 subscribers while 2000 scans of 361 beams are published: the clients that read get every
// scan in order; those that never read are dropped once their queue reaches its bound; the
// queued bytes stay within max_clients × the bound; publishing never waits for a client.
#include <gtest/gtest.h>

#include <atomic>
#include <charconv>

#include "ipc/socket/client.hpp"
#include "ipc/socket/subscription.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

namespace asio = boost::asio;
using namespace std::chrono_literals;
using ipc::socket::BeamRange;
using ipc::socket::ScanSubscription;
using ipc::socket::SocketClient;
using ipc::socket::SocketClosed;
using nlohmann::json;

constexpr std::uint64_t kScans = 2000;
constexpr std::size_t kClients = 100;
constexpr std::uint64_t kAhead = 4;  // scans the publisher runs ahead of the slowest reader

// The sequence of a scan event line, read without parsing the whole line.
std::uint64_t sequence_of(const std::string& line) {
  static const std::string key = "\"sequence\":";
  const auto at = line.find(key);
  if (line.rfind("{\"event\":\"scan\"", 0) != 0 || at == std::string::npos) {
    throw std::runtime_error("not a scan event: " + line.substr(0, 80));
  }
  std::uint64_t value = 0;
  std::from_chars(line.data() + at + key.size(), line.data() + line.size(), value);
  return value;
}

struct Reader {
  std::optional<BeamRange> beams;
  std::uint32_t every = 1;
  std::unique_ptr<SocketClient> client;
  std::vector<std::uint64_t> sequences;
  std::atomic<std::int64_t> last{-1};  // the last sequence received
  std::atomic<bool> done{false};
  std::string failure;
};

// Reads scan events until the last one its subscription takes; checks the values of every
// 100th in full.
void read_scans(Reader& r, const std::function<void()>& progressed) {
  const std::uint64_t final_sequence = (kScans - 1) / r.every * r.every;
  try {
    for (;;) {
      const auto line = r.client->read_line(kTimeout);
      if (!line) throw std::runtime_error("no scan within the timeout");
      const std::uint64_t seq = sequence_of(*line);
      r.sequences.push_back(seq);
      if (seq % 100 == 0) {
        const json scan = json::parse(*line)["scan"];
        const std::size_t first = r.beams ? r.beams->first : 0;
        const std::size_t count = r.beams ? r.beams->last - r.beams->first + 1 : 361;
        if (scan["beams"].size() != count || scan["first_beam"] != first ||
            scan["beams"][count - 1]["raw_mm"].get<double>() != raw_of(seq, first + count - 1)) {
          throw std::runtime_error("scan " + std::to_string(seq) + " has the wrong values");
        }
      }
      r.last = static_cast<std::int64_t>(seq);
      progressed();
      if (seq >= final_sequence) break;
    }
  } catch (const std::exception& e) {
    r.failure = e.what();
  }
  r.done = true;
  progressed();
}

TEST(ServerSlowClients, ReadersGetEveryScanNonReadersAreDroppedAndMemoryStaysBounded) {
  sock::SocketServerSettings settings;
  settings.max_clients = 128;
  settings.max_queued_bytes_per_client = 1u << 20;
  SocketHarness h(settings);
  h.start_server();

  std::vector<std::unique_ptr<Reader>> readers;
  const auto add_reader = [&](std::optional<BeamRange> beams, std::uint32_t every) {
    auto r = std::make_unique<Reader>();
    r->beams = beams;
    r->every = every;
    r->client = std::make_unique<SocketClient>(h.path(), kTimeout);
    const ScanSubscription subscribed(*r->client, beams, every, kTimeout);
    readers.push_back(std::move(r));
  };
  add_reader(std::nullopt, 1);
  add_reader(std::nullopt, 1);
  add_reader(BeamRange{100, 110}, 1);
  add_reader(std::nullopt, 5);
  // The rest subscribe, read the acknowledgement, and never read again.
  std::vector<std::unique_ptr<SocketClient>> idle;
  while (readers.size() + idle.size() < kClients) {
    auto client = std::make_unique<SocketClient>(h.path(), kTimeout);
    const ScanSubscription subscribed(*client, std::nullopt, 1, kTimeout);
    idle.push_back(std::move(client));
  }
  ASSERT_EQ(h.counters().subscribers, kClients);

  // The publisher, on the io thread, keeps at most kAhead scans ahead of the slowest reader
  // still reading; readers wake it through the io_context when they progress.
  asio::steady_timer wake(h.io());
  const auto progressed = [&] { asio::post(h.io(), [&] { wake.cancel(); }); };
  const auto may_publish = [&](std::uint64_t seq) {
    for (const auto& r : readers) {
      if (!r->done && static_cast<std::int64_t>(seq) - r->last.load() >
                          static_cast<std::int64_t>(kAhead + r->every)) {
        return false;
      }
    }
    return true;
  };
  std::promise<void> published;
  bool abandon = false;  // on the io thread: the test gave up waiting
  asio::co_spawn(
      h.io(),
      [&]() -> asio::awaitable<void> {
        for (std::uint64_t seq = 0; seq < kScans && !abandon;) {
          if (may_publish(seq)) {
            h.server().publish(make_scan(seq));
            ++seq;
            continue;
          }
          wake.expires_after(1s);  // a fallback only: progress cancels the wait
          boost::system::error_code ec;
          co_await wake.async_wait(asio::redirect_error(asio::use_awaitable, ec));
        }
        published.set_value();
      },
      asio::detached);

  std::vector<std::thread> threads;
  for (auto& r : readers)
    threads.emplace_back([&, reader = r.get()] { read_scans(*reader, progressed); });
  const bool finished = published.get_future().wait_for(60s) == std::future_status::ready;
  for (auto& t : threads) t.join();
  if (!finished) {
    h.on_io([&] {
      abandon = true;
      wake.cancel();
    });
  }
  ASSERT_TRUE(finished) << "2000 scans were not published within 60 s";

  for (const auto& r : readers) {
    ASSERT_EQ(r->failure, "");
    std::vector<std::uint64_t> expected;
    for (std::uint64_t seq = 0; seq < kScans; seq += r->every) expected.push_back(seq);
    EXPECT_EQ(r->sequences, expected);
  }

  const auto c = h.counters();
  EXPECT_EQ(c.scans_published, kScans);
  EXPECT_EQ(c.dropped_slow_clients, idle.size());
  EXPECT_EQ(c.clients, readers.size());
  EXPECT_LE(c.peak_client_queued_bytes, settings.max_queued_bytes_per_client);
  EXPECT_LE(c.peak_queued_bytes, settings.max_clients * settings.max_queued_bytes_per_client);
  // Full range, beams 100..110, and every fifth scan full range again (already encoded).
  EXPECT_EQ(c.scan_encodings, 2 * kScans);

  // A dropped client finds the scans that reached it, in order from the first, then the end.
  for (auto& client : idle) {
    std::uint64_t next = 0;
    try {
      while (auto line = client->read_line(kTimeout)) ASSERT_EQ(sequence_of(*line), next++);
      ADD_FAILURE() << "a dropped client's stream did not end";
    } catch (const SocketClosed&) {
    }
    EXPECT_GT(next, 0u);
    EXPECT_LT(next, kScans);
  }
  // Everything queued for the readers was written: the account returns to zero.
  EXPECT_TRUE(h.wait_for_counters([](const auto& k) { return k.queued_bytes == 0; }));
}

}  // namespace
}  // namespace tofcomp::test
