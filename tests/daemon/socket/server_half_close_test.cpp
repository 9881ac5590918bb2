// Clients that shut their side of the connection (shutdown(SHUT_WR), `nc -N`) after their
// requests: every request is answered and every reply written whole before the server ends the
// connection; a subscriber that shuts its side goes on receiving scans until it closes.
#include <gtest/gtest.h>
#include <sys/socket.h>

#include <string>

#include "ipc/socket/client.hpp"
#include "ipc/socket/subscription.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using ipc::socket::ScanSubscription;
using ipc::socket::SocketClient;
using ipc::socket::SocketClosed;
using nlohmann::json;

void shut_sending_side(SocketClient& client) {
  ASSERT_EQ(::shutdown(client.native_handle(), SHUT_WR), 0);
}

// The replies to numbered_requests(…, count), in order and each checked, then the end of the
// stream (read_line throws SocketClosed).
template <typename Check>
void expect_replies_then_the_end(SocketClient& client, int count, Check check) {
  for (int i = 0; i < count; ++i) {
    const json reply = read_json_line(client, kTimeout);
    ASSERT_EQ(reply["id"], i);
    ASSERT_EQ(reply["ok"], true);
    check(reply);
  }
  EXPECT_THROW(client.read_line(kTimeout), SocketClosed);
}

TEST(ServerHalfClose, EveryRequestSentBeforeTheClientShutsItsSideIsAnswered) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  constexpr int kRequests = 200;
  client.send_bytes(numbered_requests("status", kRequests));
  shut_sending_side(client);
  expect_replies_then_the_end(client, kRequests, [](const json&) {});
  EXPECT_TRUE(h.wait_for_counters([](const auto& c) { return c.clients == 0; }));
  EXPECT_EQ(h.counters().requests, static_cast<std::uint64_t>(kRequests));
}

// Replies of about 90 KB each, more than a socket buffer holds, and a last request without a
// line end: each reply arrives whole, then the end of the stream.
TEST(ServerHalfClose, LongRepliesAreWrittenWholeAndALastLineWithoutLineEndIsAnswered) {
  SocketHarness h;
  h.on_io([&] { h.daemon().latest = make_scan(3); });
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  constexpr int kRequests = 8;
  std::string requests = numbered_requests("latest", kRequests);
  requests.pop_back();  // the last line's '\n'
  client.send_bytes(requests);
  shut_sending_side(client);
  expect_replies_then_the_end(
      client, kRequests, [](const json& reply) { EXPECT_EQ(reply["scan"]["beams"].size(), 361u); });
}

TEST(ServerHalfClose, ASubscriberThatShutsItsSideGoesOnReceivingUntilItCloses) {
  SocketHarness h;
  h.start_server();
  {
    SocketClient client(h.path(), kTimeout);
    ScanSubscription subscription(client, std::nullopt, 1, kTimeout);
    shut_sending_side(client);
    // The scans are published once the server has seen the end of the client's input.
    const auto logged_half_close = [&h] {
      for (const std::string& line : h.log()) {
        if (line.find("shut its side; its subscription goes on") != std::string::npos) return true;
      }
      return false;
    };
    EXPECT_TRUE(h.wait_for_counters([&](const auto&) { return logged_half_close(); }));
    for (std::uint64_t seq = 0; seq < 10; ++seq) h.publish(make_scan(seq));
    for (std::uint64_t seq = 0; seq < 10; ++seq) {
      const auto scan = subscription.next(kTimeout);
      ASSERT_TRUE(scan.has_value());
      ASSERT_EQ((*scan)["sequence"], seq);
    }
  }  // closed: the next scan's write finds it gone
  for (std::uint64_t seq = 10; seq < 20; ++seq) h.publish(make_scan(seq));
  EXPECT_TRUE(h.wait_for_counters([](const auto& c) { return c.clients == 0; }));
  EXPECT_EQ(h.counters().dropped_slow_clients, 0u);
}

}  // namespace
}  // namespace tofcomp::test
