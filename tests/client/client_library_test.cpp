// libtofcomp-client against a live tofcompd (its emulated LMS 200, a private socket and ring):
// the hello states the protocol and the daemon's version; a scan read as JSON, as a compact frame
// and from the ring is the same scan; and, against stand-in daemons on real sockets, a daemon of
// another major protocol version or one without hello is refused with both versions named.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <thread>

#include "tests/daemon/e2e/daemon_process.hpp"
#include "tests/daemon/e2e/e2e_config.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using client::Connection;
using client::Error;
using client::ErrorKind;
using client::Format;

constexpr auto kTimeout = 30s;  // generous: the machine is shared

class LiveDaemon : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TemporaryDirectory();
    shm_ = "/tofcomp-client-test-" + std::to_string(::getpid());
    const auto config = dir_->path() / "tofcompd.yaml";
    write_file(config, config_text(dir_->path(), shm_,
                                   std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml"));
    daemon_ = new DaemonProcess(config, dir_->path() / "tofcompd.log");
    ASSERT_TRUE(wait_for_socket(socket(), 30s)) << daemon_->log();
  }
  static void TearDownTestSuite() {
    delete daemon_;
    delete dir_;
  }
  static std::string socket() { return (dir_->path() / "tofcompd.sock").string(); }

  static TemporaryDirectory* dir_;
  static DaemonProcess* daemon_;
  static std::string shm_;
};
TemporaryDirectory* LiveDaemon::dir_ = nullptr;
DaemonProcess* LiveDaemon::daemon_ = nullptr;
std::string LiveDaemon::shm_;

TEST_F(LiveDaemon, HelloStatesTheProtocolAndTheDaemonsVersion) {
  const Connection daemon(socket(), kTimeout);
  EXPECT_EQ(daemon.hello().protocol_major, TOFCOMP_PROTOCOL_VERSION_MAJOR);
  EXPECT_EQ(daemon.hello().protocol_minor, TOFCOMP_PROTOCOL_VERSION_MINOR);
  EXPECT_EQ(daemon.hello().daemon, "tofcompd");
  EXPECT_EQ(daemon.hello().daemon_version, TOFCOMP_PROJECT_VERSION);
  EXPECT_STREQ(client::library_version(), TOFCOMP_CLIENT_VERSION_STRING);
}

// The scans of a subscription keyed by sequence, until `count` arrived.
std::map<std::uint64_t, client::Scan> collect(Connection& daemon, std::size_t count) {
  std::map<std::uint64_t, client::Scan> scans;
  while (scans.size() < count) {
    auto scan = daemon.next_scan(kTimeout);
    if (!scan) throw std::runtime_error("no scan within 30 s");
    const std::uint64_t sequence = scan->info.sequence;
    scans.emplace(sequence, std::move(*scan));
  }
  return scans;
}

TEST_F(LiveDaemon, JsonAndCompactSubscriptionsCarryTheSameScans) {
  Connection as_json(socket(), kTimeout);
  Connection as_compact(socket(), kTimeout);
  as_json.subscribe(client::BeamRange{170, 190}, 1, Format::Json, kTimeout);
  as_compact.subscribe(client::BeamRange{170, 190}, 1, Format::Compact, kTimeout);
  const auto json_scans = collect(as_json, 8);
  const auto compact_scans = collect(as_compact, 8);
  std::size_t compared = 0;
  for (const auto& [sequence, compact] : compact_scans) {
    const auto it = json_scans.find(sequence);
    if (it == json_scans.end()) continue;
    const client::Scan& json = it->second;
    ++compared;
    EXPECT_TRUE(compact.json.empty());
    EXPECT_FALSE(json.json.empty());
    EXPECT_EQ(compact.info.timestamp_ns, json.info.timestamp_ns);
    EXPECT_EQ(compact.info.first_ray_ns, json.info.first_ray_ns);
    EXPECT_EQ(compact.info.interlaced_turns, 2u);  // 0.5°: two turns
    EXPECT_EQ(compact.info.turn_period_ns, json.info.turn_period_ns);
    EXPECT_EQ(compact.info.junction_c, json.info.junction_c);
    EXPECT_EQ(compact.info.beam_count, 361u);
    ASSERT_EQ(compact.beams.size(), 21u);
    ASSERT_EQ(json.beams.size(), 21u);
    for (std::size_t i = 0; i < compact.beams.size(); ++i) {
      EXPECT_EQ(compact.beams[i].index, 170 + i);
      EXPECT_EQ(compact.beams[i].flags, json.beams[i].flags);
      if (std::isnan(json.beams[i].compensated_mm)) {
        EXPECT_TRUE(std::isnan(compact.beams[i].compensated_mm));
      } else {  // float32 on the wire: the JSON's value rounded to float
        EXPECT_EQ(compact.beams[i].compensated_mm,
                  static_cast<double>(static_cast<float>(json.beams[i].compensated_mm)));
      }
      EXPECT_TRUE(std::isnan(compact.beams[i].raw_mm));  // not carried by a frame
      EXPECT_FALSE(std::isnan(json.beams[i].raw_mm));
    }
  }
  EXPECT_GE(compared, 4u) << "the two subscriptions shared too few sequences";
}

// Equal, or both NaN (a value that does not exist).
bool same_value(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

TEST_F(LiveDaemon, TheRingAndTheSocketHoldTheSameScan) {
  client::Ring ring(shm_);
  std::optional<client::Scan> from_ring;
  const auto until = std::chrono::steady_clock::now() + kTimeout;
  while (!(from_ring = ring.next()) && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_TRUE(from_ring.has_value()) << "no scan in the ring " << shm_ << " within 30 s";
  EXPECT_EQ(from_ring->beams.size(), from_ring->info.beam_count);
  // The socket's latest is at or after the ring's scan; subscribe and meet a later one in both.
  Connection daemon(socket(), kTimeout);
  daemon.subscribe(std::nullopt, 1, Format::Json, kTimeout);
  const auto scan = daemon.next_scan(kTimeout);
  ASSERT_TRUE(scan.has_value());
  std::optional<client::Scan> same;
  while (std::chrono::steady_clock::now() < until) {
    auto next = ring.next();
    if (!next) {
      std::this_thread::sleep_for(10ms);
      continue;
    }
    if (next->info.sequence == scan->info.sequence) {
      same = std::move(next);
      break;
    }
  }
  ASSERT_TRUE(same.has_value()) << "sequence " << scan->info.sequence << " not met in the ring";
  ASSERT_EQ(same->beams.size(), scan->beams.size());
  EXPECT_EQ(same->info.first_ray_ns, scan->info.first_ray_ns);
  for (std::size_t i = 0; i < scan->beams.size(); ++i) {
    EXPECT_TRUE(same_value(same->beams[i].raw_mm, scan->beams[i].raw_mm)) << i;
    EXPECT_TRUE(same_value(same->beams[i].compensated_mm, scan->beams[i].compensated_mm)) << i;
    EXPECT_EQ(same->beams[i].flags, scan->beams[i].flags) << i;
  }
}

TEST_F(LiveDaemon, ADaemonErrorCarriesItsCode) {
  Connection daemon(socket(), kTimeout);
  daemon.subscribe(client::BeamRange{0, 0}, 1, Format::Compact, kTimeout);
  ASSERT_TRUE(daemon.next_scan(kTimeout).has_value());  // a scan exists: the range is checked
  try {
    daemon.latest(client::BeamRange{300, 400}, kTimeout);
    ADD_FAILURE() << "beams beyond the scan were accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Daemon);
    EXPECT_EQ(e.daemon_code(), "bad_range");
  }
}

// A stand-in daemon: listens at path, answers the first line of one client with reply.
class StandIn {
 public:
  StandIn(const std::string& path, std::string reply) : path_(path) {
    fd_ = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(fd_, 1) != 0) {
      throw std::runtime_error("stand-in: cannot listen at " + path);
    }
    thread_ = std::thread([this, reply = std::move(reply)] {
      const int client = ::accept(fd_, nullptr, nullptr);
      if (client < 0) return;
      std::string received;
      char c = 0;
      while (::read(client, &c, 1) == 1 && c != '\n') received += c;
      const std::string line = reply + "\n";
      [[maybe_unused]] const auto written = ::write(client, line.data(), line.size());
      ::shutdown(client, SHUT_WR);
      while (::read(client, &c, 1) == 1) {
      }
      ::close(client);
    });
  }
  ~StandIn() {
    thread_.join();
    ::close(fd_);
    ::unlink(path_.c_str());
  }

 private:
  std::string path_;
  int fd_ = -1;
  std::thread thread_;
};

std::string refusal(const std::string& path) {
  try {
    Connection daemon(path, kTimeout);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::ProtocolVersion) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "the stand-in was accepted";
  return "";
}

TEST(ClientHello, ADaemonOfAnotherMajorVersionIsRefusedNamingBoth) {
  TemporaryDirectory dir;
  const std::string path = (dir.path() / "standin.sock").string();
  std::string message;
  {
    StandIn standin(path, R"({"id":1,"ok":true,"hello":{"protocol_major":2,"protocol_minor":3,)"
                          R"("daemon":"tofcompd","daemon_version":"9.0.0"}})");
    message = refusal(path);
  }
  EXPECT_NE(message.find("tofcompd 9.0.0 at " + path + " speaks protocol 2.3"), std::string::npos)
      << message;
  EXPECT_NE(message.find(std::string("this library (libtofcomp-client ") +
                         TOFCOMP_CLIENT_VERSION_STRING + ") speaks protocol 1.0"),
            std::string::npos)
      << message;
}

TEST(ClientHello, ADaemonWithoutHelloIsRefused) {
  TemporaryDirectory dir;
  const std::string path = (dir.path() / "standin.sock").string();
  std::string message;
  {
    StandIn standin(path, R"({"id":1,"ok":false,"error":{"code":"unknown_op",)"
                          R"("message":"op: 'hello' is not an op"}})");
    message = refusal(path);
  }
  EXPECT_NE(message.find("does not know hello"), std::string::npos) << message;
}

TEST(ClientCApi, FailuresReturnTheirStatusAndAMessage) {
  tofcomp_connection* connection = nullptr;
  EXPECT_EQ(tofcomp_connect("/nonexistent/tofcompd.sock", 1000, &connection), TOFCOMP_ERR_CONNECT);
  EXPECT_EQ(connection, nullptr);
  EXPECT_NE(std::string(tofcomp_last_error()).find("/nonexistent/tofcompd.sock"),
            std::string::npos);
  tofcomp_scan* scan = nullptr;
  EXPECT_EQ(tofcomp_decode_compact("\x89TCS", 4, &scan), TOFCOMP_ERR_BAD_DATA);
  EXPECT_NE(std::string(tofcomp_last_error()).find("fewer than the 128"), std::string::npos);
  EXPECT_EQ(tofcomp_ring_open("/tofcomp-no-such-ring", nullptr), TOFCOMP_ERR_INVALID_ARGUMENT);
  tofcomp_ring* ring = nullptr;
  EXPECT_EQ(tofcomp_ring_open("/tofcomp-no-such-ring", &ring), TOFCOMP_ERR_RING);
  EXPECT_NE(std::string(tofcomp_last_error()).find("/tofcomp-no-such-ring"), std::string::npos);
}

}  // namespace
}  // namespace tofcomp::test
