// The one writer of a shared-memory ring (docs/shm-ring.md): creates the POSIX shm object,
// publishes each compensated scan into the next slot under the slot's sequence lock, and never
// waits for readers. Not thread-safe: one thread publishes.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>

#include "ipc/compensated_scan.hpp"
#include "ipc/ring/ring_layout.hpp"
#include "ipc/ring/shm_object.hpp"

namespace tofcomp::ipc::ring {

struct RingWriterOptions {
  unsigned mode = 0640;        // permissions of the object; readers need read permission
  bool keep_on_close = false;  // leave the object (marked closed) when the writer goes away
  // When the name is taken by an object of another user (planted, perhaps, to keep the daemon
  // from starting or to feed its readers fake scans): write to alternative_ring_name(name, own
  // user) instead, leaving that object alone (true), or refuse to start (false).
  bool alternative_when_foreign = false;
};

// Throws core::InvalidInput naming the ring when the counts are outside their limits or the
// ring would pass kMaxRingBytes or the size of /dev/shm (shm_capacity_bytes). RingWriter checks
// this first; `tofcompd --check-config` too.
void check_ring_fits(const std::string& name, std::uint32_t slot_count, std::uint32_t max_beams);

class RingWriter {
 public:
  // Creates the ring `name` ("/tofcompd") with slot_count slots of max_beams beams. A ring of
  // that name of this user that no writer holds (its writer closed it or its process ended: the
  // writer's lock, shm_object.hpp) is removed first; a ring whose writer holds its lock, or an
  // object that is not a tofcomp ring, is an error. An object of another user is never touched:
  // see RingWriterOptions::alternative_when_foreign. Throws core::InvalidInput for a bad name or
  // counts, core::Error for a failed call.
  RingWriter(std::string name, std::uint32_t slot_count = kDefaultSlotCount,
             std::uint32_t max_beams = kDefaultMaxBeams, RingWriterOptions options = {});
  // Marks the ring closed, unmaps it and, unless keep_on_close, removes the name (only if it
  // still refers to this ring).
  ~RingWriter();
  RingWriter(const RingWriter&) = delete;
  RingWriter& operator=(const RingWriter&) = delete;

  // Copies scan into the next slot, overwriting the oldest. A scan with more beams than
  // max_beams is core::InvalidInput and publishes nothing.
  void publish(const CompensatedScan& scan);

  const std::string& name() const { return name_; }  // the name written to
  // When the name asked for belonged to another user: that user (name() is the alternative).
  std::optional<uid_t> foreign_owner() const { return foreign_owner_; }
  std::uint64_t published() const { return published_; }  // scans published so far
  std::uint64_t generation() const { return generation_; }
  const RingGeometry& geometry() const { return geometry_; }

 private:
  std::string name_;
  std::optional<uid_t> foreign_owner_;
  RingGeometry geometry_;
  RingWriterOptions options_;
  std::uint64_t generation_ = 0;
  std::uint64_t published_ = 0;
  ShmMapping mapping_;
};

}  // namespace tofcomp::ipc::ring
