// SystemdNotifier against the real libsystemd: NOTIFY_SOCKET points at a datagram socket this
// test binds, and each test reads back the datagram sd_notify sent.
#include "daemon/service/systemd_notifier.hpp"

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>

#include "core/error.hpp"
#include "tests/daemon/service/environment_guard.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::daemon::service {
namespace {

// A datagram socket bound in a fresh temporary directory, standing in for systemd's.
class FakeNotifySocket {
 public:
  FakeNotifySocket() : path_((directory_ / "notify.sock").string()) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    EXPECT_LT(path_.size(), sizeof(address.sun_path)) << path_;
    std::strncpy(address.sun_path, path_.c_str(), sizeof(address.sun_path) - 1);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)), 0)
        << path_ << ": " << std::strerror(errno);
  }
  FakeNotifySocket(const FakeNotifySocket&) = delete;
  FakeNotifySocket& operator=(const FakeNotifySocket&) = delete;
  ~FakeNotifySocket() { ::close(fd_); }

  const std::string& path() const { return path_; }

  // The next datagram, or "(nothing)" when none came within 10 s.
  std::string receive() const {
    pollfd ready{fd_, POLLIN, 0};
    if (::poll(&ready, 1, 10'000) != 1) return "(nothing)";
    std::array<char, 4096> buffer{};
    const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
    return n < 0 ? "(recv failed)" : std::string(buffer.data(), static_cast<std::size_t>(n));
  }

  // True when no datagram is waiting.
  bool empty() const {
    pollfd ready{fd_, POLLIN, 0};
    return ::poll(&ready, 1, 0) == 0;
  }

 private:
  test::TemporaryDirectory directory_;
  std::string path_;
  int fd_ = -1;
};

class SystemdNotifierTest : public ::testing::Test {
 protected:
  void SetUp() override { environment_.set("NOTIFY_SOCKET", socket_.path()); }

  FakeNotifySocket socket_;
  test_support::EnvironmentGuard environment_;
  SystemdNotifier notifier_;
};

TEST_F(SystemdNotifierTest, SendsEachStateAsOneDatagram) {
  EXPECT_TRUE(notifier_.enabled());
  EXPECT_EQ(notifier_.ready(), NotifyResult::Sent);
  EXPECT_EQ(socket_.receive(), "READY=1");
  EXPECT_EQ(notifier_.status("publishing 75 Hz, junction 26.4 C"), NotifyResult::Sent);
  EXPECT_EQ(socket_.receive(), "STATUS=publishing 75 Hz, junction 26.4 C");
  EXPECT_EQ(notifier_.watchdog(), NotifyResult::Sent);
  EXPECT_EQ(socket_.receive(), "WATCHDOG=1");
  EXPECT_EQ(notifier_.stopping(), NotifyResult::Sent);
  EXPECT_EQ(socket_.receive(), "STOPPING=1");
  EXPECT_TRUE(socket_.empty());
}

TEST_F(SystemdNotifierTest, StatusLineBreaksCannotInjectAnotherAssignment) {
  EXPECT_EQ(notifier_.status("bad sensor\nREADY=1\r"), NotifyResult::Sent);
  EXPECT_EQ(socket_.receive(), "STATUS=bad sensor READY=1 ");
}

TEST_F(SystemdNotifierTest, ReloadingCarriesTheMonotonicClock) {
  timespec before{};
  ::clock_gettime(CLOCK_MONOTONIC, &before);
  EXPECT_EQ(notifier_.reloading(), NotifyResult::Sent);
  timespec after{};
  ::clock_gettime(CLOCK_MONOTONIC, &after);

  const std::string message = socket_.receive();
  const std::string prefix = "RELOADING=1\nMONOTONIC_USEC=";
  ASSERT_EQ(message.substr(0, prefix.size()), prefix) << message;
  const unsigned long long usec = std::stoull(message.substr(prefix.size()));
  const auto to_usec = [](const timespec& t) {
    return static_cast<unsigned long long>(t.tv_sec) * 1'000'000ull +
           static_cast<unsigned long long>(t.tv_nsec) / 1'000ull;
  };
  EXPECT_GE(usec, to_usec(before));
  EXPECT_LE(usec, to_usec(after));
}

TEST_F(SystemdNotifierTest, WithoutNotifySocketNothingIsSent) {
  environment_.unset("NOTIFY_SOCKET");
  EXPECT_FALSE(notifier_.enabled());
  EXPECT_EQ(notifier_.ready(), NotifyResult::NoManager);
  EXPECT_EQ(notifier_.status("x"), NotifyResult::NoManager);
  EXPECT_EQ(notifier_.watchdog(), NotifyResult::NoManager);
  EXPECT_EQ(notifier_.stopping(), NotifyResult::NoManager);
  EXPECT_EQ(notifier_.reloading(), NotifyResult::NoManager);
  EXPECT_TRUE(socket_.empty());
}

TEST_F(SystemdNotifierTest, AnUnreachableSocketIsReportedNotThrown) {
  environment_.set("NOTIFY_SOCKET", socket_.path() + ".missing");
  EXPECT_EQ(notifier_.ready(), NotifyResult::Failed);
  EXPECT_TRUE(socket_.empty());
}

class WatchdogIntervalTest : public ::testing::Test {
 protected:
  test_support::EnvironmentGuard environment_;
  SystemdNotifier notifier_;
};

TEST_F(WatchdogIntervalTest, ReadsTheIntervalSystemdSetForThisProcess) {
  environment_.set("WATCHDOG_USEC", "10000000");
  environment_.set("WATCHDOG_PID", std::to_string(::getpid()));
  const auto interval = notifier_.watchdog_interval();
  ASSERT_TRUE(interval.has_value());
  EXPECT_EQ(*interval, std::chrono::seconds(10));
  EXPECT_EQ(SystemdNotifier::ping_period(*interval), std::chrono::seconds(5));
}

TEST_F(WatchdogIntervalTest, NoneWithoutTheVariables) {
  environment_.unset("WATCHDOG_USEC");
  environment_.unset("WATCHDOG_PID");
  EXPECT_FALSE(notifier_.watchdog_interval().has_value());
}

TEST_F(WatchdogIntervalTest, NoneWhenTheWatchdogIsForAnotherProcess) {
  environment_.set("WATCHDOG_USEC", "10000000");
  environment_.set("WATCHDOG_PID", std::to_string(::getpid() + 1));
  EXPECT_FALSE(notifier_.watchdog_interval().has_value());
}

TEST_F(WatchdogIntervalTest, MalformedIntervalIsAnErrorNamingIt) {
  environment_.set("WATCHDOG_USEC", "ten seconds");
  environment_.set("WATCHDOG_PID", std::to_string(::getpid()));
  try {
    (void)notifier_.watchdog_interval();
    FAIL() << "no error";
  } catch (const core::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("WATCHDOG_USEC='ten seconds'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::daemon::service
