// POSIX shared-memory objects for the ring: see shm_object.hpp.
#include "ipc/ring/shm_object.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::ipc::ring {

namespace {

[[noreturn]] void throw_errno(const std::string& name, const std::string& call, int error) {
  throw core::Error(describe_object(name) + ": " + call +
                    " failed: " + std::error_code(error, std::generic_category()).message());
}

// Closes a file descriptor when it goes out of scope.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

ShmObjectId id_of(const struct stat& st) {
  return ShmObjectId{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)};
}

}  // namespace

std::string describe_object(const std::string& name) {
  return "shm object '" + name + "'";
}

void validate_shm_name(const std::string& name) {
  const auto fail = [&](const std::string& why) {
    throw core::InvalidInput(describe_object(name) + ": invalid name: " + why +
                             " (expected '/' followed by 1 to 254 characters without '/', "
                             "e.g. /tofcompd)");
  };
  if (name.empty() || name.front() != '/') fail("it must start with '/'");
  if (name.size() < 2) fail("nothing follows the '/'");
  if (name.size() > 255) fail("it is longer than 255 characters");
  if (name.find('/', 1) != std::string::npos) fail("only its first character may be '/'");
  if (name.find('\0') != std::string::npos) fail("it contains a NUL character");
}

ShmMapping::ShmMapping(void* address, std::size_t size, ShmObjectId id, int fd, uid_t owner)
    : address_(address), size_(size), id_(id), fd_(fd), owner_(owner) {}

ShmMapping::ShmMapping(ShmMapping&& other) noexcept
    : address_(std::exchange(other.address_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      id_(other.id_),
      fd_(std::exchange(other.fd_, -1)),
      owner_(other.owner_) {}

ShmMapping& ShmMapping::operator=(ShmMapping&& other) noexcept {
  if (this != &other) {
    release();
    address_ = std::exchange(other.address_, nullptr);
    size_ = std::exchange(other.size_, 0);
    id_ = other.id_;
    fd_ = std::exchange(other.fd_, -1);
    owner_ = other.owner_;
  }
  return *this;
}

std::uint64_t ShmMapping::current_size() const {
  struct stat st {};
  if (fd_ < 0 || ::fstat(fd_, &st) != 0) return 0;
  return static_cast<std::uint64_t>(st.st_size);
}

ShmMapping::~ShmMapping() {
  release();
}

void ShmMapping::release() noexcept {
  if (address_ != nullptr) ::munmap(address_, size_);
  if (fd_ >= 0) ::close(fd_);  // drops a writer's lock
  address_ = nullptr;
  size_ = 0;
  fd_ = -1;
}

std::optional<ShmMapping> map_existing_read_only(const std::string& name) {
  validate_shm_name(name);
  FileDescriptor fd(::shm_open(name.c_str(), O_RDONLY | O_CLOEXEC, 0));
  if (fd.get() < 0) {
    if (errno == ENOENT) return std::nullopt;
    throw_errno(name, "shm_open (read-only)", errno);
  }
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) throw_errno(name, "fstat", errno);
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size == 0) return ShmMapping(nullptr, 0, id_of(st), fd.release(), st.st_uid);
  void* address = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd.get(), 0);
  if (address == MAP_FAILED) throw_errno(name, "mmap (read-only)", errno);
  return ShmMapping(address, size, id_of(st), fd.release(), st.st_uid);
}

std::optional<uid_t> object_owner(const std::string& name) {
  validate_shm_name(name);
  const FileDescriptor fd(::shm_open(name.c_str(), O_RDONLY | O_CLOEXEC, 0));
  struct stat st {};
  if (fd.get() >= 0) {
    if (::fstat(fd.get(), &st) != 0) throw_errno(name, "fstat", errno);
    return st.st_uid;
  }
  if (errno == ENOENT) return std::nullopt;
  // Shut out by its mode: its owner is still to be seen in the directory.
  const std::string path = std::string(kShmDirectory) + name;
  if (::lstat(path.c_str(), &st) == 0) return st.st_uid;
  if (errno == ENOENT) return std::nullopt;
  throw_errno(name, "stat " + path, errno);
}

bool writer_lock_held(int fd, const std::string& name) {
  struct flock probe {};
  probe.l_type = F_WRLCK;
  probe.l_whence = SEEK_SET;
  probe.l_start = 0;
  probe.l_len = 0;  // the whole object
  if (::fcntl(fd, F_OFD_GETLK, &probe) != 0) throw_errno(name, "fcntl(F_OFD_GETLK)", errno);
  return probe.l_type != F_UNLCK;
}

std::optional<ShmObjectId> identify_object(const std::string& name) {
  const FileDescriptor fd(::shm_open(name.c_str(), O_RDONLY | O_CLOEXEC, 0));
  if (fd.get() < 0) {
    if (errno == ENOENT) return std::nullopt;
    throw_errno(name, "shm_open (read-only)", errno);
  }
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) throw_errno(name, "fstat", errno);
  return id_of(st);
}

std::uint64_t shm_capacity_bytes() {
  struct statvfs st {};
  if (::statvfs(kShmDirectory, &st) != 0) throw_errno(kShmDirectory, "statvfs", errno);
  return static_cast<std::uint64_t>(st.f_blocks) * st.f_frsize;
}

ShmMapping create_exclusive(const std::string& name, std::size_t bytes, unsigned mode) {
  validate_shm_name(name);
  FileDescriptor fd(
      ::shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR | O_CLOEXEC, static_cast<mode_t>(mode)));
  if (fd.get() < 0) throw_errno(name, "shm_open (O_CREAT | O_EXCL)", errno);
  struct stat st {};
  try {
    struct flock lock {};
    lock.l_type = F_WRLCK;
    lock.l_whence = SEEK_SET;
    lock.l_start = 0;
    lock.l_len = 0;  // the whole object, however it grows
    if (::fcntl(fd.get(), F_OFD_SETLK, &lock) != 0) {
      throw_errno(name, "fcntl(F_OFD_SETLK): taking the writer's lock", errno);
    }
    if (::fchmod(fd.get(), static_cast<mode_t>(mode)) != 0) throw_errno(name, "fchmod", errno);
    if (::ftruncate(fd.get(), static_cast<off_t>(bytes)) != 0) {
      throw_errno(name, "ftruncate to " + std::to_string(bytes) + " bytes", errno);
    }
    // The pages are reserved now: where /dev/shm is too small the start fails here, named,
    // instead of a SIGBUS at the first write to a page beyond what it holds.
    if (const int error = ::posix_fallocate(fd.get(), 0, static_cast<off_t>(bytes)); error != 0) {
      throw_errno(name, "reserving " + std::to_string(bytes) + " bytes (posix_fallocate; " +
                            std::string(kShmDirectory) + " holds " +
                            std::to_string(shm_capacity_bytes()) + ")",
                  error);
    }
    if (::fstat(fd.get(), &st) != 0) throw_errno(name, "fstat", errno);
    void* address = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd.get(), 0);
    if (address == MAP_FAILED) throw_errno(name, "mmap (read-write)", errno);
    return ShmMapping(address, bytes, id_of(st), fd.release(), st.st_uid);
  } catch (...) {
    ::shm_unlink(name.c_str());
    throw;
  }
}

std::string alternative_ring_name(const std::string& name, uid_t uid) {
  return name + "." + std::to_string(uid);
}

void unlink_object(const std::string& name) {
  if (::shm_unlink(name.c_str()) != 0 && errno != ENOENT) throw_errno(name, "shm_unlink", errno);
}

bool unlink_object_if(const std::string& name, ShmObjectId id) {
  const auto now = identify_object(name);
  if (!now || !(*now == id)) return false;
  return ::shm_unlink(name.c_str()) == 0;
}

}  // namespace tofcomp::ipc::ring
