// The ring against other users and against its own object going wrong (issue 15): a ring whose
// writer died is replaced even when its pid now belongs to another process (the writer's lock,
// not the pid, says whether it runs); a ring planted under the name by another user is left
// alone, the writer takes the alternative name and readers follow it, or refuse the planted one
// naming its owner; a reader whose object is truncated under it gets an error, not SIGBUS.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <optional>
#include <string>

#include "core/error.hpp"
#include "ipc/ring/ring_header.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "ipc/ring/shm_object.hpp"
#include "tests/ipc/ring/ring_test_support.hpp"
#include "tests/support/planted_ring.hpp"

namespace tofcomp::ipc::ring {
namespace {

using testing::difference;
using testing::known_scan;
using testing::run_in_child;
using testing::ScopedRingName;

constexpr uid_t kNobody = tofcomp::test::PlantedRing::kNobody;
constexpr pid_t kInit = 1;  // a process that always runs

// A writer in a child process publishes `scans` known scans and ends without closing its ring
// (as a crash or kill -9 leaves it).
int leave_ring_behind(const std::string& name, std::uint64_t first, int scans) {
  try {
    auto* leaked = new RingWriter(name, 8, 4);
    for (int s = 0; s < scans; ++s) leaked->publish(known_scan(first + s, 4));
    return 0;
  } catch (...) {
    return 1;
  }
}

// Rewrites the header's writer_pid of ring `name`, as a reused pid would make it.
void set_writer_pid(const std::string& name, std::int32_t pid) {
  const int fd = ::shm_open(name.c_str(), O_RDWR, 0);
  ASSERT_GE(fd, 0);
  void* base = ::mmap(nullptr, sizeof(RingHeader), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ASSERT_NE(base, MAP_FAILED);
  reinterpret_cast<RingHeader*>(base)->writer_pid = pid;
  ::munmap(base, sizeof(RingHeader));
  ::close(fd);
}

TEST(RingTrust, ADeadWritersRingIsReplacedEvenWhenItsPidRunsAgain) {
  const ScopedRingName name("reused-pid");
  ASSERT_EQ(run_in_child([&] { return leave_ring_behind(name, 0, 3); }), 0);
  set_writer_pid(name, kInit);  // the dead writer's pid now names a running process
  RingReader reader(name);
  EXPECT_EQ(reader.info().writer_pid, kInit);
  EXPECT_FALSE(reader.writer_running());  // nobody holds its lock
  RingWriter restarted(name, 8, 4);
  restarted.publish(known_scan(7, 4));
  EXPECT_EQ(reader.latest()->sequence, 7u);
  EXPECT_TRUE(reader.writer_running());
}

TEST(RingTrust, TheWritersLockNotItsPidSaysItRuns) {
  const ScopedRingName name("lock");
  RingWriter writer(name, 4, 4);
  RingReader reader(name);
  EXPECT_TRUE(reader.writer_running());
  set_writer_pid(name, 0);  // whatever the header says
  EXPECT_TRUE(reader.writer_running());
}

// Runs `body` in a child process whose /dev/shm is a tmpfs of `size` (mounted in a mount
// namespace of its own, in a user namespace too when this user may not mount) and returns what
// it returns; nullopt when this machine allows neither namespace.
std::optional<std::string> with_small_shm(const char* size, std::string (*body)()) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return std::nullopt;
  const uid_t uid = ::geteuid();
  const gid_t gid = ::getegid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(pipe_fds[0]);
    const auto write_file = [](const char* path, const std::string& text) {
      const int fd = ::open(path, O_WRONLY);
      const bool ok =
          fd >= 0 && ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
      if (fd >= 0) ::close(fd);
      return ok;
    };
    bool isolated = ::unshare(CLONE_NEWNS) == 0;
    if (!isolated && ::unshare(CLONE_NEWUSER | CLONE_NEWNS) == 0) {
      isolated =
          write_file("/proc/self/setgroups", "deny") &&
          write_file("/proc/self/uid_map",
                     std::to_string(uid) + " " + std::to_string(uid) + " 1") &&
          write_file("/proc/self/gid_map", std::to_string(gid) + " " + std::to_string(gid) + " 1");
    }
    if (!isolated || ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
        ::mount("tmpfs", kShmDirectory, "tmpfs", 0, (std::string("size=") + size).c_str()) != 0) {
      ::_exit(2);
    }
    const std::string result = body();
    const bool written =
        ::write(pipe_fds[1], result.data(), result.size()) == static_cast<ssize_t>(result.size());
    ::_exit(written ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string result;
  char buffer[4096];
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) result.append(buffer, n);
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) == 2) return std::nullopt;
  return result;
}

std::string error_of_writer(std::uint32_t slots) {
  try {
    RingWriter writer("/tofcomp-small-shm", slots, 1024);
    writer.publish(known_scan(0, 1024));
    return "(made, and written)";
  } catch (const core::Error& e) {
    return std::string(e.what()) +
           (identify_object("/tofcomp-small-shm") ? " (an object was left)" : "");
  }
}

// A /dev/shm smaller than the ring (a container's): the writer's start fails naming the sizes.
// Before, the ring was sized with ftruncate alone and its first write to a page beyond the
// tmpfs killed the daemon with SIGBUS.
TEST(RingTrust, ARingLargerThanSharedMemoryIsRefusedAtItsStart) {
  const auto error = with_small_shm("1m", [] { return error_of_writer(64); });  // 3.7 MB
  if (!error) GTEST_SKIP() << "no mount namespace on this machine";
  EXPECT_NE(error->find("64 slots of 1024 beams need 3678336 bytes, more than /dev/shm holds "
                        "(1048576)"),
            std::string::npos)
      << *error;
}

// One that fits the tmpfs but not what is free in it: every page is reserved at the start, so
// the start fails (ENOSPC, named) and nothing is left behind.
TEST(RingTrust, ARingLargerThanTheFreeSharedMemoryIsRefusedAtItsStart) {
  const auto error = with_small_shm("1m", [] {
    const int fd = ::shm_open("/tofcomp-filler", O_CREAT | O_RDWR, 0600);
    if (fd < 0 || ::posix_fallocate(fd, 0, 768 << 10) != 0) return std::string("(no filler)");
    return error_of_writer(8);  // 460 KB
  });
  if (!error) GTEST_SKIP() << "no mount namespace on this machine";
  EXPECT_NE(error->find("reserving 459904 bytes (posix_fallocate; /dev/shm holds 1048576)"),
            std::string::npos)
      << *error;
  EXPECT_NE(error->find("No space left on device"), std::string::npos) << *error;
  EXPECT_EQ(error->find("an object was left"), std::string::npos) << *error;
}

TEST(RingTrust, AShrunkObjectIsAnErrorNotSigbus) {
  const ScopedRingName name("shrunk");
  auto writer = std::make_unique<RingWriter>(name, 8, 64);
  for (std::uint64_t s = 0; s < 5; ++s) writer->publish(known_scan(s, 64));
  RingReader reader(name);
  reader.rewind_to_oldest();
  EXPECT_EQ(reader.read_new().scans.size(), 5u);
  writer->publish(known_scan(5, 64));
  // Truncated under the reader's mapping (by its owner, the one user who may).
  const int fd = ::shm_open(name.str().c_str(), O_RDWR, 0);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, 64), 0);
  ::close(fd);
  const std::string expected =
      "shm object '" + name.str() + "' shrank to 64 bytes while it was read";
  for (int call = 0; call < 4; ++call) {
    try {
      if (call == 0) reader.read_new();
      if (call == 1) reader.latest();
      if (call == 2) reader.info();
      if (call == 3) reader.writer_running();
      ADD_FAILURE() << "call " << call << " read the truncated ring";
    } catch (const core::Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
    }
  }
  writer.reset();  // the writer's own pages: its header's page is still there
}

TEST(RingTrust, ARingPlantedByAnotherUserIsLeftAloneAndReadersFollowTheAlternative) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to plant a ring as another user";
  const ScopedRingName name("planted");
  const std::string alternative = alternative_ring_name(name, ::geteuid());
  ::shm_unlink(alternative.c_str());
  // Another user makes a complete ring under the name first, with a fake scan in it, and even
  // holds its writer's lock while the daemon starts.
  const tofcomp::test::PlantedRing planted(name);

  // A writer that may not take an alternative refuses, naming the owner; the object stays.
  try {
    RingWriter refused(name, 8, 4);
    ADD_FAILURE() << "took the planted name";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to uid 65534"), std::string::npos) << e.what();
  }
  // Readers refuse the planted ring while tofcompd has no alternative.
  try {
    RingReader reader(name);
    ADD_FAILURE() << "read the planted ring";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to uid 65534"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(alternative), std::string::npos) << e.what();
  }
  {
    RingWriter writer(name, 8, 4, RingWriterOptions{0640, false, true});
    EXPECT_EQ(writer.name(), alternative);
    EXPECT_EQ(writer.foreign_owner(), kNobody);
    writer.publish(known_scan(1, 4));
    RingReader reader(name);
    EXPECT_EQ(reader.name(), alternative);
    EXPECT_EQ(reader.foreign_owner(), kNobody);
    const auto latest = reader.latest();
    ASSERT_TRUE(latest.has_value());
    EXPECT_EQ(difference(*latest, known_scan(1, 4)), "");  // the real scan, not the fake
    // A reader that accepts the other user too reads the planted ring: the owners decide.
    RingReader trusting(name, RingReaderOptions{{kNobody}});
    EXPECT_EQ(trusting.latest()->sequence, tofcomp::test::PlantedRing::kFakeSequence);
  }
  struct stat st {};
  EXPECT_EQ(::stat(("/dev/shm" + name.str()).c_str(), &st), 0);  // left where it was
  EXPECT_EQ(st.st_uid, kNobody);
}

}  // namespace
}  // namespace tofcomp::ipc::ring
