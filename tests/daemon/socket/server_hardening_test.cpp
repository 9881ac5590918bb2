// The server against clients that read but may not control, that stay silent, and that pipeline
// requests (issue 15): control requests are answered forbidden for users other than the
// daemon's own and root (by SO_PEERCRED, here a real process of another user); a silent client's
// slot is freed after the idle timeout, a silent subscriber's only while nothing is delivered;
// a client that sends many requests at once and then reads gets every reply, in order.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

#include "ipc/socket/client.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using ipc::socket::SocketClient;
using ipc::socket::SocketClosed;
using nlohmann::json;

constexpr uid_t kNobody = 65534;  // Debian's nobody: a user that is neither root nor this one

TEST(ServerAuthorization, ControlIsForbiddenToUsersNotAllowedReadingIsNot) {
  sock::SocketServerSettings settings;
  settings.control_uids = {::geteuid() + 4242};  // not this test's user: it may only read
  SocketHarness h(settings);
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  const json reload = client.request({{"id", 1}, {"op", "reload"}}, kTimeout);
  EXPECT_EQ(reload["ok"], false);
  EXPECT_EQ(reload["error"]["code"], "forbidden");
  const std::string message = reload["error"]["message"];
  EXPECT_EQ(message.rfind("reload: not allowed for uid " + std::to_string(::geteuid()), 0), 0u)
      << message;
  EXPECT_NE(message.find("control requests (reload, recalibrate) are for uid " +
                         std::to_string(::geteuid() + 4242) + " only"),
            std::string::npos)
      << message;
  const json recalibrate =
      client.request({{"op", "recalibrate"}, {"args", {{"recording", "/dev/zero"}}}}, kTimeout);
  EXPECT_EQ(recalibrate["error"]["code"], "forbidden");
  // The daemon was never asked.
  EXPECT_EQ(h.on_io([&] { return h.daemon().reloads; }), 0);
  EXPECT_TRUE(h.on_io([&] { return h.daemon().recalibrate_args.empty(); }));
  // Reading goes on, on the same connection.
  EXPECT_TRUE(client.call({{"op", "status"}}, kTimeout)["ok"]);
  EXPECT_TRUE(client.call({{"op", "stats"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.counters().forbidden_requests, 2u);
}

TEST(ServerAuthorization, TheServersOwnUserAndRootMayControlByDefault) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  EXPECT_TRUE(client.call({{"op", "reload"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.on_io([&] { return h.daemon().reloads; }), 1);
}

// What a process of user `uid` is answered for `requests`: one reply line per request, or the
// error it met, as the child wrote them to a pipe.
std::vector<std::string> answers_as_user(const std::string& path, uid_t uid,
                                         const std::vector<std::string>& requests) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) throw std::runtime_error("pipe failed");
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(pipe_fds[0]);
    std::string out;
    if (::setgid(uid) != 0 || ::setuid(uid) != 0) {
      out = "setuid failed\n";
    } else {
      try {
        SocketClient client(path, 10s);
        for (const auto& r : requests) {
          client.send_line(r);
          const auto line = client.read_line(10s);
          out += (line ? *line : std::string("no reply")) + "\n";
        }
      } catch (const std::exception& e) {
        out += std::string("error: ") + e.what() + "\n";
      }
    }
    const ssize_t written = ::write(pipe_fds[1], out.data(), out.size());
    ::_exit(written == static_cast<ssize_t>(out.size()) ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) {
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(pipe_fds[0]);
  ::waitpid(child, nullptr, 0);
  std::vector<std::string> lines;
  for (std::size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos;
       start = end + 1) {
    lines.push_back(text.substr(start, end - start));
  }
  return lines;
}

TEST(ServerAuthorization, AProcessOfAnotherUserReadsButCannotControl) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to run a client as another user";
  sock::SocketServerSettings settings;
  settings.permissions = 0666;  // so that nobody may connect at all
  SocketHarness h(settings);
  ASSERT_EQ(::chmod(h.dir().c_str(), 0755), 0);
  h.start_server();
  const auto answers = answers_as_user(
      h.path(), kNobody,
      {R"({"id":1,"op":"reload"})", R"({"id":2,"op":"recalibrate","args":{"recording":"x.csv"}})",
       R"({"id":3,"op":"status"})"});
  ASSERT_EQ(answers.size(), 3u) << (answers.empty() ? "" : answers[0]);
  EXPECT_EQ(json::parse(answers[0])["error"]["code"], "forbidden") << answers[0];
  EXPECT_NE(answers[0].find("not allowed for uid 65534"), std::string::npos) << answers[0];
  EXPECT_EQ(json::parse(answers[1])["error"]["code"], "forbidden") << answers[1];
  EXPECT_EQ(json::parse(answers[2])["ok"], true) << answers[2];
  EXPECT_EQ(h.on_io([&] { return h.daemon().reloads; }), 0);
  EXPECT_TRUE(h.on_io([&] { return h.daemon().recalibrate_args.empty(); }));
}

// The idle line, naming the timeout as `span`, then the end of the stream.
void expect_closed_as_idle(SocketClient& client, const std::string& span) {
  const json told = read_json_line(client, kTimeout);
  EXPECT_EQ(told["error"]["code"], "unavailable");
  EXPECT_EQ(told["error"]["message"], "connection: no request and nothing delivered for " + span +
                                          " (idle_timeout_s); closing it to free its slot");
  EXPECT_THROW(client.read_line(kTimeout), SocketClosed);
}

TEST(ServerIdleTimeout, ASilentClientsSlotIsFreed) {
  sock::SocketServerSettings settings;
  settings.max_clients = 1;
  settings.idle_timeout = 200ms;
  SocketHarness h(settings);
  h.start_server();
  SocketClient silent(h.path(), kTimeout);
  // The silent client is told why, then the stream ends.
  expect_closed_as_idle(silent, "200 ms");
  ASSERT_TRUE(h.wait_for_counters([](const auto& c) { return c.clients == 0; }));
  // Its slot is free: the next client is served.
  SocketClient next(h.path(), kTimeout);
  EXPECT_TRUE(next.call({{"op", "status"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.counters().idle_clients_closed, 1u);
}

// Idle is "no request and nothing delivered" (issue 53: subscribers whose `every` brought them
// nothing held their slots for ever): a subscriber sent scans stays, however silent; one whose
// subscription brings it nothing is told and closed like any silent client.
TEST(ServerIdleTimeout, ASubscriberIsIdleOnlyWhileNothingIsDeliveredToIt) {
  sock::SocketServerSettings settings;
  settings.idle_timeout = 2s;
  SocketHarness h(settings);
  h.start_server();
  SocketClient served(h.path(), kTimeout);
  ASSERT_TRUE(served.call({{"op", "subscribe"}, {"beams", {0, 0}}}, kTimeout)["ok"]);
  SocketClient starved(h.path(), kTimeout);
  ASSERT_TRUE(starved.call({{"op", "subscribe"}, {"every", 1000000}}, kTimeout)["ok"]);
  // Scans every 20 ms (a hundredth of the timeout) until the starved subscriber is closed.
  std::uint64_t sequence = 1;  // never a multiple of 1000000 here: the starved one gets none
  const auto until = std::chrono::steady_clock::now() + kTimeout;
  while (h.counters().idle_clients_closed == 0 && std::chrono::steady_clock::now() < until) {
    h.publish(make_scan(sequence++, 1));
    std::this_thread::sleep_for(20ms);
  }
  expect_closed_as_idle(starved, "2 s");
  // The served one got every scan and is still served.
  for (std::uint64_t s = 1; s < sequence; ++s) {
    EXPECT_EQ(read_json_line(served, kTimeout)["scan"]["sequence"], s);
  }
  h.publish(make_scan(sequence, 1));
  EXPECT_EQ(read_json_line(served, kTimeout)["scan"]["sequence"], sequence);
  EXPECT_EQ(h.counters().idle_clients_closed, 1u);
}

TEST(ServerBackPressure, AClientThatPipelinesRequestsGetsEveryReplyInOrder) {
  sock::SocketServerSettings settings;
  settings.max_queued_bytes_per_client = 4096;  // the smallest bound; each reply is ~90 KB
  SocketHarness h(settings);
  h.on_io([&] { h.daemon().latest = make_scan(3); });
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  constexpr int kRequests = 50;
  client.send_bytes(numbered_requests("latest", kRequests));
  for (int i = 0; i < kRequests; ++i) {
    const json reply = read_json_line(client, kTimeout);
    ASSERT_EQ(reply["id"], i);
    ASSERT_EQ(reply["ok"], true) << reply.dump().substr(0, 200);
    ASSERT_EQ(reply["scan"]["beams"].size(), 361u);
  }
  const auto counters = h.counters();
  EXPECT_EQ(counters.dropped_slow_clients, 0u);
  EXPECT_EQ(counters.requests, static_cast<std::uint64_t>(kRequests));
  // Requests waited while a reply was queued: one reply beyond half the bound at most.
  EXPECT_LE(counters.peak_client_queued_bytes, 4096u / 2 + 100000u);
}

TEST(ServerBackPressure, ASubscriberThatDoesNotReadIsStillDropped) {
  sock::SocketServerSettings settings;
  settings.max_queued_bytes_per_client = 4096;
  SocketHarness h(settings);
  h.start_server();
  SocketClient subscriber(h.path(), kTimeout);
  ASSERT_TRUE(subscriber.call({{"op", "subscribe"}}, kTimeout)["ok"]);
  // Full scans, never read: the socket's buffer fills, then the queue passes its bound.
  for (std::uint64_t s = 0; s < 200 && h.counters().dropped_slow_clients == 0; ++s) {
    h.publish(make_scan(s));
  }
  EXPECT_EQ(h.counters().dropped_slow_clients, 1u);
}

}  // namespace
}  // namespace tofcomp::test
