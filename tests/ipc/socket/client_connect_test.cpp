// The client's connection errors name the path and say what to check.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "ipc/socket/client.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::ipc::socket {
namespace {

using namespace std::chrono_literals;

TEST(ClientConnect, MissingSocketSaysNoSuchFileAndAsksWhetherTheDaemonRuns) {
  const test::TemporaryDirectory directory("tofcomp-client", test::kSocketParent);
  const std::string path = (directory / "tofcompd.sock").string();
  try {
    SocketClient client(path, 1s);
    FAIL() << "connected";
  } catch (const core::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot connect to " + path + ": No such file or directory; is tofcompd running?");
  }
}

TEST(ClientConnect, SocketFileWithNobodyListeningIsRefused) {
  const test::TemporaryDirectory directory("tofcomp-client", test::kSocketParent);
  const std::string path = (directory / "stale.sock").string();
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
