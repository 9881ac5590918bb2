// The socket file: a stale one is removed, a live one (another daemon) or a file that is not a
// socket stops start-up, permissions are set, and stop removes the file and ends connections.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "ipc/socket/client.hpp"
#include "tests/daemon/socket/server_harness.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using ipc::socket::SocketClient;
using ipc::socket::SocketClosed;

// A socket file nobody listens on, as a daemon that died leaves it.
void make_stale_socket(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ::close(fd);
}

bool logged(const SocketHarness& h, const std::string& text) {
  const auto log = h.log();
  return std::any_of(log.begin(), log.end(),
                     [&](const std::string& m) { return m.find(text) != std::string::npos; });
}

TEST(ServerSocketFile, StaleSocketFileIsRemovedAndTheServerListens) {
  SocketHarness h;
  make_stale_socket(h.path());
  ASSERT_TRUE(std::filesystem::exists(h.path()));
  h.start_server();
  EXPECT_TRUE(logged(h, "socket: removed the stale socket file " + h.path()));
  SocketClient client(h.path(), kTimeout);
  EXPECT_TRUE(client.call({{"op", "status"}}, kTimeout)["ok"]);
}

TEST(ServerSocketFile, SecondServerOnALivePathIsRefusedAndTheFirstGoesOn) {
  SocketHarness h;
  h.start_server();
  EXPECT_EQ(h.start_server_error(),
            "another tofcompd is listening on " + h.path() + "; not starting a second");
  SocketClient client(h.path(), kTimeout);
  EXPECT_TRUE(client.call({{"op", "status"}}, kTimeout)["ok"]);
}

TEST(ServerSocketFile, PathHoldingSomethingElseIsLeftAloneAndStartFails) {
  SocketHarness h;
  std::ofstream(h.path()) << "not a socket\n";
  EXPECT_EQ(h.start_server_error(), "the socket path " + h.path() +
                                        " exists and is not a socket; remove it or choose "
                                        "another path");
  EXPECT_TRUE(std::filesystem::is_regular_file(h.path()));
}

TEST(ServerSocketFile, MissingDirectoryIsNamed) {
  SocketHarness h;
  h.set_path(h.dir() + "/no-such-dir/tofcompd.sock");
  EXPECT_EQ(h.start_server_error(),
            "cannot bind the socket " + h.path() +
                ": No such file or directory (its directory does not exist)");
}

TEST(ServerSocketFile, PermissionsAreSet) {
  sock::SocketServerSettings settings;
  settings.permissions = 0640;
  SocketHarness h(settings);
  h.start_server();
  struct stat st {};
  ASSERT_EQ(::stat(h.path().c_str(), &st), 0);
  EXPECT_TRUE(S_ISSOCK(st.st_mode));
  EXPECT_EQ(st.st_mode & 0777, 0640u);
}

// A client that finds the path can connect at once, and the file already has its permissions:
// the server binds under a hidden name and gives the socket the path only once it listens.
TEST(ServerSocketFile, ThePathAppearsListeningWithItsPermissions) {
  sock::SocketServerSettings settings;
  settings.permissions = 0600;
  SocketHarness h(settings);
  struct Seen {
    bool appeared = false;
    int connect_result = -1;
    int connect_errno = 0;
    unsigned mode = 0;
  } seen;
  std::thread watcher([&] {
    const auto deadline = std::chrono::steady_clock::now() + kTimeout;
    struct stat st {};
    while (std::chrono::steady_clock::now() < deadline) {
      if (::lstat(h.path().c_str(), &st) != 0) continue;
      seen.appeared = true;
      seen.mode = st.st_mode & 0777;
      const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
      sockaddr_un address{};
      address.sun_family = AF_UNIX;
      std::strcpy(address.sun_path, h.path().c_str());
      seen.connect_result = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
      seen.connect_errno = errno;
      ::close(fd);
      return;
    }
  });
  h.start_server();
  watcher.join();
  ASSERT_TRUE(seen.appeared);
  EXPECT_EQ(seen.connect_result, 0) << std::strerror(seen.connect_errno);
  EXPECT_EQ(seen.mode, 0600u);
  // Nothing but the socket is left in its directory.
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(h.dir())) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(names, std::vector<std::string>{"tofcompd.sock"});
}

TEST(ServerSocketFile, StopRemovesTheFileAndEndsConnectionsAndStartListensAgain) {
  SocketHarness h;
  h.start_server();
  SocketClient client(h.path(), kTimeout);
  EXPECT_TRUE(client.call({{"op", "status"}}, kTimeout)["ok"]);
  h.on_io([&] { h.server().stop(); });
  EXPECT_FALSE(std::filesystem::exists(h.path()));
  EXPECT_THROW(client.read_line(kTimeout), SocketClosed);
  h.on_io([&] { h.server().start(); });
  SocketClient again(h.path(), kTimeout);
  EXPECT_TRUE(again.call({{"op", "status"}}, kTimeout)["ok"]);
  EXPECT_EQ(h.counters().clients, 1u);
}

}  // namespace
}  // namespace tofcomp::test
