// Where a daemon publishes by default and where a client looks, for root and for another user
// (ipc/default_places.hpp). The expected paths are the XDG Base Directory specification's and
// docs/deployment.md's, written out here.
#include "ipc/default_places.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>
#include <fcntl.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace tofcomp::ipc {
namespace {

namespace fs = std::filesystem;

// A uid no account on a test machine has, so that its ring name is nobody's.
constexpr uid_t kUserUid = 3999001;

UserEnvironment user(std::string runtime, std::string state, std::string home) {
  return {kUserUid, std::move(runtime), std::move(state), std::move(home)};
}

TEST(DefaultPlaces, RootGetsTheSystemsPlacesWhateverItsEnvironment) {
  const DaemonPlaces places = daemon_places({0, "/run/user/0", "/root/state", "/root"});
  EXPECT_TRUE(places.system);
  EXPECT_EQ(places.socket, "/run/tofcompd/tofcompd.sock");
  EXPECT_EQ(places.ring, "/tofcompd");
  EXPECT_EQ(places.state_directory, "/var/lib/tofcompd");
}

TEST(DefaultPlaces, AnotherUserGetsItsOwnRuntimeAndStateFolders) {
  const DaemonPlaces places = daemon_places(user("/run/user/3999001", "/home/u/.state", "/home/u"));
  EXPECT_FALSE(places.system);
  EXPECT_EQ(places.socket, "/run/user/3999001/tofcompd/tofcompd.sock");
  EXPECT_EQ(places.ring, "/tofcompd.3999001");
  EXPECT_EQ(places.state_directory, "/home/u/.state/tofcompd");
}

TEST(DefaultPlaces, TheStateFallsBackToHomeAndTheRuntimeToAFolderOfTheUid) {
  const DaemonPlaces places = daemon_places(user("", "", "/home/u"));
  EXPECT_EQ(places.socket, "/tmp/tofcompd-3999001/tofcompd.sock");
  EXPECT_EQ(places.state_directory, "/home/u/.local/state/tofcompd");
  // Without a home either, the state goes under the runtime folder.
  EXPECT_EQ(daemon_places(user("", "", "")).state_directory, "/tmp/tofcompd-3999001/state");
}

TEST(DefaultPlaces, RelativeXdgDirectoriesAreIgnored) {
  const DaemonPlaces places = daemon_places(user("run/user/1", "state", "/home/u"));
  EXPECT_EQ(places.socket, "/tmp/tofcompd-3999001/tofcompd.sock");
  EXPECT_EQ(places.state_directory, "/home/u/.local/state/tofcompd");
}

class ClientDefaults : public ::testing::Test {
 protected:
  void SetUp() override {
    runtime_ = fs::temp_directory_path() / ("tofcomp-places-" + std::to_string(::getpid()));
    fs::create_directories(runtime_);
  }
  void TearDown() override {
    fs::remove_all(runtime_);
    ::shm_unlink(own_ring().c_str());
  }
  std::string own_ring() const { return "/tofcompd." + std::to_string(kUserUid); }
  fs::path runtime_;
};

TEST_F(ClientDefaults, AUserReadsTheSystemsDaemonUntilItsOwnRuns) {
  const UserEnvironment environment = user(runtime_.string(), "", "/home/u");
  EXPECT_EQ(socket_to_read(environment), "/run/tofcompd/tofcompd.sock");
  EXPECT_EQ(ring_to_read(environment), "/tofcompd");

  // The user's own daemon: its socket (a real one, bound) and its ring.
  fs::create_directories(runtime_ / "tofcompd");
  const fs::path own_socket = runtime_ / "tofcompd" / "tofcompd.sock";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, own_socket.c_str(), sizeof address.sun_path - 1);
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  const int ring = ::shm_open(own_ring().c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  ASSERT_GE(ring, 0) << std::strerror(errno);
  ::close(ring);

  EXPECT_EQ(socket_to_read(environment), own_socket);
  EXPECT_EQ(ring_to_read(environment), own_ring());
  ::close(fd);
}

TEST_F(ClientDefaults, RootReadsTheSystemsDaemonEvenWhenAUsersRuns) {
  fs::create_directories(runtime_ / "tofcompd");
  std::ofstream(runtime_ / "tofcompd" / "tofcompd.sock") << "";
  EXPECT_EQ(socket_to_read({0, runtime_.string(), "", "/root"}), "/run/tofcompd/tofcompd.sock");
}

}  // namespace
}  // namespace tofcomp::ipc
