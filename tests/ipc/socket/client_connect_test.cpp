// The client's connection errors name the path and say what to check.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "ipc/socket/client.hpp"

namespace tofcomp::ipc::socket {
namespace {

using namespace std::chrono_literals;

std::string temp_dir() {
  char pattern[] = "/tmp/tofcomp-client-XXXXXX";
  const char* dir = ::mkdtemp(pattern);
  if (dir == nullptr) throw std::runtime_error("mkdtemp failed");
  return dir;
}

TEST(ClientConnect, MissingSocketSaysNoSuchFileAndAsksWhetherTheDaemonRuns) {
  const std::string path = temp_dir() + "/tofcompd.sock";
  try {
    SocketClient client(path, 1s);
    FAIL() << "connected";
  } catch (const core::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot connect to " + path + ": No such file or directory; is tofcompd running?");
  }
}

TEST(ClientConnect, SocketFileWithNobodyListeningIsRefused) {
  const std::string path = temp_dir() + "/stale.sock";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ::close(fd);  // the file stays, nobody listens
  try {
    SocketClient client(path, 1s);
    FAIL() << "connected";
  } catch (const core::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot connect to " + path + ": Connection refused; is tofcompd running?");
  }
}

TEST(ClientConnect, PathTooLongForAUnixSocketIsInvalidInput) {
  EXPECT_THROW(SocketClient(std::string(200, 'p'), 1s), core::InvalidInput);
  EXPECT_THROW(SocketClient("", 1s), core::InvalidInput);
}

}  // namespace
}  // namespace tofcomp::ipc::socket
