// The one writer of a shared-memory ring: see ring_writer.hpp.
#include "ipc/ring/ring_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <ctime>
#include <mutex>
#include <set>

#include "core/error.hpp"
#include "ipc/ring/ring_header.hpp"
#include "ipc/ring/seqlock_slot.hpp"
#include "ipc/user_name.hpp"

namespace tofcomp::ipc::ring {

namespace {

// Names held by the RingWriters of this process, so that a second writer of one name in the
// same process is refused by name before it looks at the object.
std::mutex& names_mutex() {
  static std::mutex m;
  return m;
}
std::set<std::string>& names_held() {
  static std::set<std::string> names;
  return names;
}

void claim_name(const std::string& name) {
  const std::lock_guard lock(names_mutex());
  if (!names_held().insert(name).second) {
    throw core::Error(describe_object(name) +
                      ": another RingWriter of this process already writes it");
  }
}

void release_name(const std::string& name) noexcept {
  const std::lock_guard lock(names_mutex());
  names_held().erase(name);
}

// Removes a ring of this name (this user's) left by a writer that is gone, and returns its
// generation (0 if there was none). Refuses to remove a ring whose writer holds its lock, or an
// object that is not a tofcomp ring.
std::uint64_t retire_stale_ring(const std::string& name) {
  const auto existing = map_existing_read_only(name);
  if (!existing) return 0;
  std::uint64_t previous_generation = 0;
  if (writer_lock_held(existing->fd(), name)) {
    const std::int32_t pid =
        existing->size() >= sizeof(RingHeader) ? read_header(existing->data()).writer_pid : 0;
    throw core::Error(describe_object(name) + " is in use by a running writer (pid " +
                      std::to_string(pid) +
                      ", which holds its lock); stop it or choose another "
                      "name");
  }
  if (existing->size() >= sizeof(RingHeader)) {
    const RingHeader h = read_header(existing->data());
    if (h.magic != 0 && h.magic != kRingMagic) {
      throw core::Error(describe_object(name) +
                        " exists and is not a tofcomp ring (no TOFCRING magic); it was left "
                        "in place: remove it (rm /dev/shm" +
                        name + ") or choose another name");
    }
    if (h.magic == kRingMagic) previous_generation = h.generation;
  }
  unlink_object_if(name, existing->id());
  return previous_generation;
}

std::uint64_t new_generation(std::uint64_t previous) {
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  const std::uint64_t ns = static_cast<std::uint64_t>(now.tv_sec) * 1'000'000'000u +
                           static_cast<std::uint64_t>(now.tv_nsec);
  return std::max(ns, previous + 1);
}

}  // namespace

void check_ring_fits(const std::string& name, std::uint32_t slot_count, std::uint32_t max_beams) {
  const std::string what = describe_object(name);
  if (slot_count < kMinSlotCount || slot_count > kMaxSlotCount) {
    throw core::InvalidInput(what + ": slot count " + std::to_string(slot_count) + " is outside " +
                             std::to_string(kMinSlotCount) + ".." + std::to_string(kMaxSlotCount));
  }
  if (max_beams < 1 || max_beams > kMaxBeamsLimit) {
    throw core::InvalidInput(what + ": max beams " + std::to_string(max_beams) + " is outside 1.." +
                             std::to_string(kMaxBeamsLimit));
  }
  const std::uint64_t bytes = ring_size_for(slot_count, max_beams);
  const std::string need = what + ": " + std::to_string(slot_count) + " slots of " +
                           std::to_string(max_beams) + " beams need " + std::to_string(bytes) +
                           " bytes, more than ";
  if (bytes > kMaxRingBytes) {
    throw core::InvalidInput(need + "the limit of " + std::to_string(kMaxRingBytes));
  }
  const std::uint64_t capacity = shm_capacity_bytes();
  if (bytes > capacity) {
    throw core::InvalidInput(need + kShmDirectory + " holds (" + std::to_string(capacity) + ")");
  }
}

RingWriter::RingWriter(std::string name, std::uint32_t slot_count, std::uint32_t max_beams,
                       RingWriterOptions options)
    : name_(std::move(name)), geometry_{slot_count, max_beams}, options_(options) {
  validate_shm_name(name_);
  check_ring_fits(name_, slot_count, max_beams);
  const uid_t self = ::geteuid();
  if (const auto owner = object_owner(name_); owner && *owner != self) {
    const std::string taken = describe_object(name_) + " belongs to " + describe_user(*owner) +
                              ", not to this writer's " + describe_user(self) +
                              ": another user made it; it is left alone";
    if (!options_.alternative_when_foreign) {
      throw core::Error(taken + " (remove it as root, rm /dev/shm" + name_ +
                        ", or choose another name)");
    }
    foreign_owner_ = owner;
    name_ = alternative_ring_name(name_, self);
    validate_shm_name(name_);
    if (const auto second = object_owner(name_); second && *second != self) {
      throw core::Error(taken + ", and so is its alternative " + describe_object(name_) + " (" +
                        describe_user(*second) + ")");
    }
  }
  claim_name(name_);
  try {
    generation_ = new_generation(retire_stale_ring(name_));
    mapping_ = create_exclusive(name_, geometry_.ring_size(), options_.mode);
    initialise_header(mapping_.data(), geometry_, static_cast<std::int32_t>(::getpid()),
                      generation_);
    publish_magic(mapping_.data());
  } catch (...) {
    if (mapping_.data() != nullptr) unlink_object_if(name_, mapping_.id());
    release_name(name_);
    throw;
  }
}

RingWriter::~RingWriter() {
  store_writer_state(mapping_.data(), kWriterClosed);
  if (!options_.keep_on_close) {
    try {
      unlink_object_if(name_, mapping_.id());
    } catch (const std::exception&) {
      // The name may have become unreadable; the mapping is released all the same.
    }
  }
  release_name(name_);
}

void RingWriter::publish(const CompensatedScan& scan) {
  if (scan.beams.size() > geometry_.max_beams) {
    throw core::InvalidInput(describe_object(name_) + ": scan " + std::to_string(scan.sequence) +
                             " has " + std::to_string(scan.beams.size()) +
                             " beams, more than the ring's max_beams of " +
                             std::to_string(geometry_.max_beams) + "; nothing was published");
  }
  write_slot(mapping_.data() + geometry_.slot_offset(published_), published_, scan);
  ++published_;
  store_published(mapping_.data(), published_);
}

}  // namespace tofcomp::ipc::ring
