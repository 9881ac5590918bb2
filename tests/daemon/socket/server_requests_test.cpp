// The server answers each op through the daemon's handler, over a real Unix socket: known
// replies, every error code the server itself gives, and a connection that survives bad lines.
#include <gtest/gtest.h>

#include "ipc/socket/client.hpp"
#include "ipc/socket/protocol_error.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using ipc::socket::SocketClient;
using nlohmann::json;

TEST(ServerRequests, LatestBeforeAnyScanIsUnavailable) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  const json reply = client.request({{"id", 1}, {"op", "latest"}}, kTimeout);
  EXPECT_EQ(reply, json::parse(R"({"id":1,"ok":false,"error":{"code":"unavailable",)"
                               R"("message":"latest: no scan has been published yet"}})"));
}

TEST(ServerRequests, LatestReturnsTheHandlersScanForTheBeamsAsked) {
  SocketHarness h;
  h.daemon().latest = make_scan(42, 361);
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  const json all = client.call({{"id", "a"}, {"op", "latest"}}, kTimeout);
  EXPECT_EQ(all["id"], "a");
  EXPECT_EQ(all["scan"]["sequence"], 42);
  EXPECT_EQ(all["scan"]["beams"].size(), 361u);
  const json part = client.call({{"op", "latest"}, {"beams", {100, 102}}}, kTimeout);
  const json& scan = part["scan"];
  EXPECT_EQ(scan["beam_count"], 361);
  EXPECT_EQ(scan["first_beam"], 100);
  ASSERT_EQ(scan["beams"].size(), 3u);
  EXPECT_EQ(scan["beams"][0]["index"], 100);
  EXPECT_EQ(scan["beams"][0]["raw_mm"].get<double>(), raw_of(42, 100));
  EXPECT_TRUE(scan["beams"][0]["window_mm"].is_null());  // NaN in memory
  EXPECT_EQ(scan["beams"][0]["flag_names"], json::array({"window_restarting"}));
  EXPECT_EQ(scan["beams"][2]["compensated_mm"].get<double>(), raw_of(42, 102) - 12.5);
}

TEST(ServerRequests, LatestBeyondTheScanIsBadRangeNamingBeams) {
  SocketHarness h;
  h.daemon().latest = make_scan(1, 181);
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  const json reply = client.request({{"id", 5}, {"op", "latest"}, {"beams", {0, 200}}}, kTimeout);
  EXPECT_EQ(reply["error"]["code"], "bad_range");
  EXPECT_EQ(reply["error"]["message"],
            "beams: [0, 200] reaches beyond the scan, which has 181 beams (0..180)");
  EXPECT_EQ(reply["id"], 5);
}

TEST(ServerRequests, StatusAndStatsCarryTheHandlersDocumentsAndTheSocketCounters) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  EXPECT_EQ(client.call({{"id", 1}, {"op", "status"}}, kTimeout),
            json::parse(R"({"id":1,"ok":true,"status":{"link":"streaming","scans":12}})"));
  const json stats = client.call({{"id", 2}, {"op", "stats"}}, kTimeout);
  EXPECT_EQ(stats["stats"], h.daemon().stats_doc);
  EXPECT_EQ(stats["socket"]["clients"], 1);
  EXPECT_EQ(stats["socket"]["requests"], 2);  // this one counted before it is answered
  EXPECT_EQ(stats["socket"]["errors"], 0);
}

TEST(ServerRequests, ReloadAcceptedAndRefused) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  EXPECT_EQ(client.call({{"id", 1}, {"op", "reload"}}, kTimeout),
            json::parse(R"({"id":1,"ok":true,"message":"reloaded calibration 3"})"));
  h.on_io([&] { h.daemon().reload_result = {false, "calibration.yaml: line 4: bad order"}; });
  EXPECT_EQ(client.request({{"id", 2}, {"op", "reload"}}, kTimeout),
            json::parse(R"({"id":2,"ok":false,"error":{"code":"refused",)"
                        R"("message":"reload: calibration.yaml: line 4: bad order"}})"));
  EXPECT_EQ(h.on_io([&] { return h.daemon().reloads; }), 2);
}

TEST(ServerRequests, RecalibratePassesItsArgsAndReportsRefusalAndBadArgs) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  EXPECT_EQ(client.call({{"op", "recalibrate"}, {"args", {{"minutes", 10}}}}, kTimeout)["message"],
            "recalibration started");
  client.call({{"op", "recalibrate"}}, kTimeout);
  EXPECT_EQ(h.on_io([&] { return h.daemon().recalibrate_args; }),
            (std::vector<json>{{{"minutes", 10}}, json::object()}));
  h.on_io([&] { h.daemon().recalibration_result = {false, "a recalibration is running"}; });
  const json refused = client.request({{"op", "recalibrate"}}, kTimeout);
  EXPECT_EQ(refused["error"]["code"], "refused");
  EXPECT_EQ(refused["error"]["message"], "recalibrate: a recalibration is running");
  h.on_io([&] { h.daemon().recalibrate_invalid = "args.minutes: must be positive"; });
  const json bad = client.request({{"op", "recalibrate"}, {"args", {{"minutes", -1}}}}, kTimeout);
  EXPECT_EQ(bad["error"]["code"], "bad_request");
  EXPECT_EQ(bad["error"]["message"], "args.minutes: must be positive");
}

TEST(ServerRequests, AHandlerFailureIsAnInternalErrorAndTheServerGoesOn) {
  SocketHarness h;
  h.daemon().status_throws = true;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  EXPECT_EQ(client.request({{"id", 1}, {"op", "status"}}, kTimeout),
            json::parse(R"({"id":1,"ok":false,"error":{"code":"internal",)"
                        R"("message":"internal error: the status table is gone"}})"));
  EXPECT_TRUE(client.call({{"op", "stats"}}, kTimeout)["ok"]);
}

TEST(ServerRequests, MalformedLinesGetErrorsAndTheConnectionSurvives) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  client.send_line("{oops");
  const json bad = read_json_line(client, kTimeout);
  EXPECT_FALSE(bad.contains("id"));
  EXPECT_EQ(bad["error"]["code"], "bad_request");
  EXPECT_EQ(bad["error"]["message"].get<std::string>().rfind("request: not valid JSON", 0), 0u);
  client.send_line(R"({"id":2,"op":"fetch"})");
  EXPECT_EQ(read_json_line(client, kTimeout)["error"]["code"], "unknown_op");
  client.send_line(R"({"id":3,"op":"subscribe","every":0})");
  EXPECT_EQ(read_json_line(client, kTimeout),
            json::parse(R"({"id":3,"ok":false,"error":{"code":"bad_range",)"
                        R"("message":"every: 0 is outside 1..1000000"}})"));
  // Blank lines are skipped; a '\r' before the '\n' is allowed.
  client.send_bytes("\n\r\n{\"id\":4,\"op\":\"status\"}\r\n");
  EXPECT_EQ(read_json_line(client, kTimeout)["id"], 4);
  // Two requests in one write, answered in order.
  client.send_bytes("{\"id\":5,\"op\":\"stats\"}\n{\"id\":6,\"op\":\"status\"}\n");
  EXPECT_EQ(read_json_line(client, kTimeout)["id"], 5);
  EXPECT_EQ(read_json_line(client, kTimeout)["id"], 6);
  // A request split over several writes.
  client.send_bytes("{\"id\":7,");
  client.send_bytes("\"op\":\"sta");
  client.send_bytes("tus\"}\n");
  EXPECT_EQ(read_json_line(client, kTimeout)["id"], 7);
  const auto c = h.counters();
  EXPECT_EQ(c.requests, 7u);
  EXPECT_EQ(c.errors, 3u);
}

TEST(ServerRequests, SeveralClientsAreAnsweredIndependently) {
  SocketHarness h;
  h.start_server();
  SocketClient a(h.path(), kTimeout);
  SocketClient b(h.path(), kTimeout);
  a.send_line(R"({"id":"a1","op":"status"})");
  b.send_line(R"({"id":"b1","op":"stats"})");
  EXPECT_EQ(read_json_line(b, kTimeout)["id"], "b1");
  EXPECT_EQ(read_json_line(a, kTimeout)["id"], "a1");
}

}  // namespace
}  // namespace tofcomp::test
