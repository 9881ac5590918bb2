// Subscriptions over a real Unix socket: published scans arrive in order with their values, each
// subscription's beams and decimation, one encoding per distinct beam range, unsubscribe.
#include <gtest/gtest.h>

#include "ipc/socket/client.hpp"
#include "ipc/socket/compact_frame.hpp"
#include "ipc/socket/subscription.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using ipc::socket::BeamRange;
using ipc::socket::ScanSubscription;
using ipc::socket::SocketClient;
using nlohmann::json;

// Room for every scan these tests publish before their subscribers read: 100 full scans of
// about 90 KB each (the bound itself is tested in server_slow_clients_test.cpp).
sock::SocketServerSettings roomy() {
  sock::SocketServerSettings settings;
  settings.max_queued_bytes_per_client = 16u << 20;
  return settings;
}

json next_scan(ScanSubscription& subscription) {
  auto scan = subscription.next(kTimeout);
  if (!scan) throw std::runtime_error("no scan within the timeout");
  return *scan;
}

TEST(ServerSubscribe, HundredScansArriveInOrderWithValuesRangesAndDecimation) {
  SocketHarness h(roomy());
  h.start_server();
  SocketClient every_client(h.path(), kTimeout);
  SocketClient twin_client(h.path(), kTimeout);
  SocketClient decimated_client(h.path(), kTimeout);
  ScanSubscription every(every_client, std::nullopt, 1, kTimeout);
  ScanSubscription twin(twin_client, std::nullopt, 1, kTimeout);
  ScanSubscription decimated(decimated_client, BeamRange{2, 4}, 3, kTimeout);
  EXPECT_EQ(every.acknowledged(), json::parse(R"({"beams":null,"every":1,"format":"json"})"));
  EXPECT_EQ(decimated.acknowledged(), json::parse(R"({"beams":[2,4],"every":3,"format":"json"})"));
  EXPECT_EQ(h.counters().subscribers, 3u);

  for (std::uint64_t seq = 0; seq < 100; ++seq) h.publish(make_scan(seq));

  for (std::uint64_t seq = 0; seq < 100; ++seq) {
    for (ScanSubscription* s : {&every, &twin}) {
      const json scan = next_scan(*s);
      ASSERT_EQ(scan["sequence"], seq);
      ASSERT_EQ(scan["device_sequence"], seq + 5);
      ASSERT_EQ(scan["beams"].size(), 361u);
      ASSERT_EQ(scan["beams"][7]["raw_mm"].get<double>(), raw_of(seq, 7));
      ASSERT_EQ(scan["beams"][360]["compensated_mm"].get<double>(), raw_of(seq, 360) - 12.5);
    }
  }
  for (std::uint64_t seq = 0; seq < 100; seq += 3) {
    const json scan = next_scan(decimated);
    ASSERT_EQ(scan["sequence"], seq);
    ASSERT_EQ(scan["first_beam"], 2);
    ASSERT_EQ(scan["beams"].size(), 3u);
    ASSERT_EQ(scan["beams"][0]["index"], 2);
    ASSERT_EQ(scan["beams"][2]["raw_mm"].get<double>(), raw_of(seq, 4));
  }
  const auto c = h.counters();
  EXPECT_EQ(c.scans_published, 100u);
  // Full range: one encoding per scan for both subscribers; beams 2..4: one per third scan.
  EXPECT_EQ(c.scan_encodings, 100u + 34u);
}

// A compact subscriber and a JSON one of the same beams: frames interleaved with a reply, each
// frame the scan's compensated ranges and flags; one encoding per scan for each format.
TEST(ServerSubscribe, CompactFramesCarryTheScansBesideJsonLines) {
  SocketHarness h(roomy());
  h.start_server();
  SocketClient compact(h.path(), kTimeout);
  SocketClient lines(h.path(), kTimeout);
  const json ack =
      compact.call(json{{"op", "subscribe"}, {"beams", {10, 12}}, {"format", "compact"}}, kTimeout);
  EXPECT_EQ(ack["subscription"], json::parse(R"({"beams":[10,12],"every":1,"format":"compact"})"));
  ScanSubscription as_json(lines, BeamRange{10, 12}, 1, kTimeout);
  for (std::uint64_t seq = 0; seq < 5; ++seq) h.publish(make_scan(seq));
  // A request while frames are queued: its reply is a line among the frames.
  EXPECT_TRUE(compact.call(json{{"op", "hello"}}, kTimeout)["hello"]["protocol_major"] == 1);
  for (std::uint64_t seq = 0; seq < 5; ++seq) {
    auto message = compact.read_any(kTimeout);
    ASSERT_TRUE(message.has_value());
    ASSERT_TRUE(message->is_frame());
    const auto frame = ipc::socket::decode_compact_frame(message->frame);
    EXPECT_EQ(frame.scan.sequence, seq);
    EXPECT_EQ(frame.span, (ipc::socket::BeamSpan{10, 3}));
    EXPECT_EQ(frame.scan.beams[12].compensated_mm, static_cast<float>(raw_of(seq, 12) - 12.5));
    EXPECT_EQ(next_scan(as_json)["sequence"], seq);
  }
  EXPECT_EQ(h.counters().scan_encodings, 5u * 2u);
}

TEST(ServerSubscribe, NothingArrivesAfterTheUnsubscribeReply) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  ScanSubscription subscription(client, std::nullopt, 1, kTimeout);
  h.publish(make_scan(0, 5));
  h.publish(make_scan(1, 5));
  subscription.unsubscribe(kTimeout);
  h.publish(make_scan(2, 5));
  EXPECT_TRUE(client.call({{"op", "status"}}, kTimeout)["ok"]);
  // Scans 0 and 1 were kept aside while waiting for the replies; scan 2 was never sent.
  EXPECT_EQ((*client.read_message(0ms))["scan"]["sequence"], 0);
  EXPECT_EQ((*client.read_message(0ms))["scan"]["sequence"], 1);
  EXPECT_FALSE(client.read_message(0ms).has_value());
  EXPECT_EQ(h.counters().subscribers, 0u);
}

TEST(ServerSubscribe, ASecondSubscribeReplacesTheFirst) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  ScanSubscription first(client, std::nullopt, 1, kTimeout);
  ScanSubscription second(client, BeamRange{1, 1}, 2, kTimeout);
  for (std::uint64_t seq = 0; seq < 4; ++seq) h.publish(make_scan(seq, 5));
  EXPECT_EQ(next_scan(second)["sequence"], 0);
  const json scan = next_scan(second);
  EXPECT_EQ(scan["sequence"], 2);
  EXPECT_EQ(scan["beams"].size(), 1u);
}

TEST(ServerSubscribe, RangeBeyondTheLatestScanIsRefusedAndLaterScansAreClipped) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  // No scan yet: the range is taken, and a narrower scan is clipped to what it has.
  ScanSubscription subscription(client, BeamRange{170, 200}, 1, kTimeout);
  h.publish(make_scan(0, 181));
  const json scan = next_scan(subscription);
  EXPECT_EQ(scan["beam_count"], 181);
  EXPECT_EQ(scan["first_beam"], 170);
  EXPECT_EQ(scan["beams"].size(), 11u);
  // With a latest scan at hand, a range beyond it is refused at once.
  h.on_io([&] { h.daemon().latest = make_scan(0, 181); });
  SocketClient other(h.path(), kTimeout);
  const json reply = other.request({{"op", "subscribe"}, {"beams", {0, 181}}}, kTimeout);
  EXPECT_EQ(reply["error"]["code"], "bad_range");
  EXPECT_EQ(reply["error"]["message"],
            "beams: [0, 181] reaches beyond the scan, which has 181 beams (0..180)");
}

TEST(ServerSubscribe, SubscriberThatHangsUpMidStreamIsForgotten) {
  SocketHarness h(roomy());
  h.start_server();
  SocketClient staying_client(h.path(), kTimeout);
  ScanSubscription staying(staying_client, std::nullopt, 1, kTimeout);
  {
    SocketClient leaving_client(h.path(), kTimeout);
    ScanSubscription leaving(leaving_client, std::nullopt, 1, kTimeout);
    for (std::uint64_t seq = 0; seq < 10; ++seq) h.publish(make_scan(seq));
  }  // closed with scans unread
  for (std::uint64_t seq = 10; seq < 50; ++seq) h.publish(make_scan(seq));
  for (std::uint64_t seq = 0; seq < 50; ++seq) ASSERT_EQ(next_scan(staying)["sequence"], seq);
  EXPECT_TRUE(h.wait_for_counters([](const auto& c) { return c.clients == 1; }));
  EXPECT_EQ(h.counters().dropped_slow_clients, 0u);
}

}  // namespace
}  // namespace tofcomp::test
