// The server's limits: an over-long request is answered too_long and its connection closed
// cleanly after the answer; clients beyond max_clients get an error line and are closed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>

#include "ipc/socket/client.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using ipc::socket::SocketClient;
using ipc::socket::SocketClosed;
using nlohmann::json;

// The next read ends the stream: end of file, not a reset.
void expect_clean_close(SocketClient& client) {
  try {
    client.read_line(kTimeout);
    ADD_FAILURE() << "the connection is still open";
  } catch (const SocketClosed& e) {
    EXPECT_NE(std::string(e.what()).find("closed the connection"), std::string::npos) << e.what();
  }
}

TEST(ServerLimits, RequestWithoutLineEndBeyondTheLimitIsTooLongThenClosed) {
  SocketHarness h;
  h.start_server();
  SocketClient other(h.path(), kTimeout);
  SocketClient client(h.path(), kTimeout);
  client.send_bytes(std::string(10000, 'a'));
  EXPECT_EQ(read_json_line(client, kTimeout),
            json::parse(R"j({"ok":false,"error":{"code":"too_long","message":)j"
                        R"j("request: more than 4096 bytes without a line end (the limit of a )j"
                        R"j(request)"}})j"));
  expect_clean_close(client);
  EXPECT_TRUE(other.call({{"op", "status"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.counters().errors, 1u);
}

TEST(ServerLimits, CompleteLineBeyondTheLimitIsTooLongThenClosed) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  const std::string line = R"({"op":"status","id":")" + std::string(5000, 'i') + "\"}";
  client.send_line(line);
  const json reply = read_json_line(client, kTimeout);
  EXPECT_EQ(reply["error"]["code"], "too_long");
  EXPECT_EQ(reply["error"]["message"], "request: " + std::to_string(line.size()) +
                                           " bytes, more than the limit of 4096 bytes");
  expect_clean_close(client);
}

TEST(ServerLimits, RequestsBeforeTheOverLongOneAreAnswered) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  client.send_bytes("{\"id\":1,\"op\":\"status\"}\n" + std::string(9000, '{'));
  EXPECT_EQ(read_json_line(client, kTimeout)["id"], 1);
  EXPECT_EQ(read_json_line(client, kTimeout)["error"]["code"], "too_long");
  expect_clean_close(client);
}

TEST(ServerLimits, ClientsBeyondMaxClientsGetAnErrorLineAndAreClosed) {
  sock::SocketServerSettings settings;
  settings.max_clients = 2;
  settings.control_uids = {::geteuid() + 4242};  // this test's user only reads: no operator slot
  SocketHarness h(settings);
  h.start_server();
  auto a = std::make_unique<SocketClient>(h.path(), kTimeout);
  SocketClient b(h.path(), kTimeout);
  EXPECT_TRUE(a->call({{"op", "status"}}, kTimeout)["ok"]);
  EXPECT_TRUE(b.call({{"op", "status"}}, kTimeout)["ok"]);
  SocketClient c(h.path(), kTimeout);
  EXPECT_EQ(read_json_line(c, kTimeout),
            json::parse(R"j({"ok":false,"error":{"code":"unavailable","message":)j"
                        R"j("connection: too many clients; 2 are connected, the most the daemon )j"
                        R"j(serves (max_clients)"}})j"));
  expect_clean_close(c);
  EXPECT_EQ(h.counters().refused_clients, 1u);
  a.reset();
  ASSERT_TRUE(h.wait_for_counters([](const auto& k) { return k.clients == 1; }));
  SocketClient d(h.path(), kTimeout);
  EXPECT_TRUE(d.call({{"op", "status"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.counters().clients, 2u);
}

// A flood of connections beyond max_clients is counted one by one but logged once per 10 s, the
// next warning with the count of those not logged (issue 53: each one was logged).
TEST(ServerLimits, ConnectionsTurnedAwayAreLoggedAtARateLimit) {
  sock::SocketServerSettings settings;
  settings.max_clients = 1;
  settings.control_uids = {::geteuid() + 4242};  // a reader: no operator slot
  SocketHarness h(settings);
  h.start_server();
  SocketClient admitted(h.path(), kTimeout);
  EXPECT_TRUE(admitted.call({{"op", "status"}}, kTimeout)["ok"]);
  constexpr int kTurnedAway = 50;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kTurnedAway; ++i) {
    SocketClient refused(h.path(), kTimeout);
    EXPECT_EQ(read_json_line(refused, kTimeout)["error"]["code"], "unavailable");
  }
  const auto elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_EQ(h.counters().refused_clients, static_cast<std::uint64_t>(kTurnedAway));
  const auto logs = h.log();
  const auto warnings = std::count_if(logs.begin(), logs.end(), [](const std::string& line) {
    return line.find("turned away") != std::string::npos;
  });
  // One warning per 10 s begun (the loop above takes well under a second here).
  EXPECT_GE(warnings, 1);
  EXPECT_LE(warnings, 1 + elapsed / std::chrono::seconds(10));
}

// Readers holding every slot cannot lock out the operator (issue 53: 16 subscribers and root's
// reload got "too many clients"): a user who may control the daemon gets one slot beyond
// max_clients, one only, and its slot is free again once it goes.
TEST(ServerLimits, TheOperatorHasASlotBeyondMaxClients) {
  sock::SocketServerSettings settings;
  settings.max_clients = 2;  // this test's user is the server's own: it may control
  SocketHarness h(settings);
  h.start_server();
  SocketClient a(h.path(), kTimeout);
  SocketClient b(h.path(), kTimeout);
  ASSERT_TRUE(a.call({{"op", "subscribe"}}, kTimeout)["ok"]);
  ASSERT_TRUE(b.call({{"op", "subscribe"}}, kTimeout)["ok"]);
  {
    SocketClient operator_client(h.path(), kTimeout);
    EXPECT_TRUE(operator_client.call({{"op", "reload"}}, kTimeout)["ok"]);
    EXPECT_EQ(h.on_io([&] { return h.daemon().reloads; }), 1);
    EXPECT_EQ(h.counters().clients, 3u);
    // The operator's slot is one: a second operator connection meanwhile is turned away.
    SocketClient second(h.path(), kTimeout);
    EXPECT_EQ(read_json_line(second, kTimeout)["error"]["code"], "unavailable");
    expect_clean_close(second);
  }
  ASSERT_TRUE(h.wait_for_counters([](const auto& k) { return k.clients == 2; }));
  SocketClient again(h.path(), kTimeout);
  EXPECT_TRUE(again.call({{"op", "reload"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.counters().refused_clients, 1u);
}

TEST(ServerLimits, SettingsAreValidatedNamingTheSetting) {
  boost::asio::io_context io;
  FakeDaemon daemon;
  sock::SocketServerSettings s;
  s.max_clients = 0;
  try {
    sock::SocketServer server(io, s, daemon);
    FAIL();
  } catch (const core::InvalidInput& e) {
    EXPECT_STREQ(e.what(), "socket server: max_clients: must be at least 1");
  }
  s = {};
  s.path = std::string(120, 'p');
  EXPECT_THROW(sock::SocketServer(io, s, daemon), core::InvalidInput);
  s = {};
  s.max_request_bytes = 10;
  EXPECT_THROW(sock::SocketServer(io, s, daemon), core::InvalidInput);
  s = {};
  s.permissions = 01777;
  EXPECT_THROW(sock::SocketServer(io, s, daemon), core::InvalidInput);
}

}  // namespace
}  // namespace tofcomp::test
