// POSIX shared-memory objects as the ring uses them: name checks, exclusive creation with a
// fixed mode, read-only opening, whole-object mappings that unmap themselves (and keep their
// object open, to see its size and owner now), the writer's lock, and removal of a name only
// while it still refers to the object one created. Errors are core::Error with the object's name
// and the failed call.
//
// The writer's lock: the writer holds an open-file-description write lock (F_OFD_SETLK) on the
// whole object for as long as it writes; the kernel drops it when the writer's process ends,
// however it ends. A ring whose lock nobody holds has no writer, whatever pid its header names
// (a pid is reused; a lock is not).
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace tofcomp::ipc::ring {

// How messages name an object: "shm object '/tofcompd'".
std::string describe_object(const std::string& name);

// Throws core::InvalidInput unless name is a portable POSIX shm name: '/' followed by 1 to 254
// characters, none of them '/' or NUL.
void validate_shm_name(const std::string& name);

// Which object a name referred to when it was opened (its tmpfs device and inode): a name
// re-created by another writer refers to another object.
struct ShmObjectId {
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
  bool operator==(const ShmObjectId&) const = default;
};

// A mapping of a whole shm object, unmapped (and its descriptor closed) on destruction. An object
// of 0 bytes has no mapping: data() is null and size() is 0.
class ShmMapping {
 public:
  ShmMapping() = default;
  ShmMapping(void* address, std::size_t size, ShmObjectId id, int fd, uid_t owner);
  ShmMapping(ShmMapping&& other) noexcept;
  ShmMapping& operator=(ShmMapping&& other) noexcept;
  ShmMapping(const ShmMapping&) = delete;
  ShmMapping& operator=(const ShmMapping&) = delete;
  ~ShmMapping();

  std::byte* data() const { return static_cast<std::byte*>(address_); }
  std::size_t size() const { return size_; }  // when it was mapped
  ShmObjectId id() const { return id_; }
  uid_t owner() const { return owner_; }  // the object's owner when it was opened
  int fd() const { return fd_; }
  // The object's size now: a reader checks it before touching the mapping, since a page of a
  // mapping beyond the end of a shrunk object raises SIGBUS.
  std::uint64_t current_size() const;

 private:
  void release() noexcept;
  void* address_ = nullptr;
  std::size_t size_ = 0;
  ShmObjectId id_;
  int fd_ = -1;
  uid_t owner_ = 0;
};

// Opens name read-only and maps all of it read-only; nullopt when no object has that name.
std::optional<ShmMapping> map_existing_read_only(const std::string& name);

// The identity of the object name refers to now; nullopt when none.
std::optional<ShmObjectId> identify_object(const std::string& name);

// Where POSIX shared memory objects live on Linux (a tmpfs), and its size in bytes. Throws
// core::Error naming it when it cannot be read.
inline constexpr const char* kShmDirectory = "/dev/shm";
std::uint64_t shm_capacity_bytes();

// Creates name (O_CREAT | O_EXCL: fails if it exists) with exactly `mode` (set with fchmod, so
// the umask does not narrow it), takes the writer's lock on it, sizes it to `bytes`
// (zero-filled, every page reserved: too large for /dev/shm is an error naming both sizes) and
// maps it read-write. The lock is held while the mapping lives. On failure nothing is left
// behind.
ShmMapping create_exclusive(const std::string& name, std::size_t bytes, unsigned mode);

// The owner of the object name refers to; nullopt when none. Found even when the object cannot
// be opened (its mode shuts this user out), through /dev/shm.
std::optional<uid_t> object_owner(const std::string& name);

// Whether some writer holds the writer's lock on the object open as fd (any open descriptor of
// it, read-only included). Takes no lock itself.
bool writer_lock_held(int fd, const std::string& name);

// The name a writer takes when `name` belongs to another user, and where readers then look:
// "/tofcompd.999" for "/tofcompd" and uid 999 (docs/shm-ring.md).
std::string alternative_ring_name(const std::string& name, uid_t uid);

// Removes name; no error when it does not exist.
void unlink_object(const std::string& name);

// Removes name only if it still refers to object `id`; returns whether it did.
bool unlink_object_if(const std::string& name, ShmObjectId id);

}  // namespace tofcomp::ipc::ring
