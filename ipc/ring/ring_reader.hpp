// A reader of tofcompd's shared-memory ring (docs/shm-ring.md): opens the ring read-only,
// checks its header, and copies scans out under the slots' sequence locks. Copies torn by the
// writer are discarded and counted, never returned. A reader that falls more than a ring behind
// is told how many scans it lost; a writer that re-created the ring is detected and followed.
// Trust: a ring is read only when it belongs to one of the accepted users (by default this
// process's, root and tofcompd's); when the name belongs to someone else, the reader looks where
// tofcompd then publishes (alternative_ring_name, shm_object.hpp) or refuses, naming the owner.
// The object's size is checked (fstat) before each access, so a ring shrunk while mapped is an
// error, not a SIGBUS. One RingReader per thread; any number of readers per ring, in any
// processes.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ipc/compensated_scan.hpp"
#include "ipc/ring/ring_layout.hpp"
#include "ipc/ring/shm_object.hpp"

namespace tofcomp::ipc::ring {

// What the header of the ring being read says now.
struct RingInfo {
  std::string name;
  std::uint32_t layout_version = 0;
  std::uint32_t slot_count = 0;
  std::uint32_t max_beams = 0;
  std::uint32_t max_modes = 0;
  std::uint32_t slot_size = 0;
  std::int32_t writer_pid = 0;
  std::uint64_t generation = 0;
  bool writer_closed = false;   // its writer closed it: no more scans will come to this ring
  std::uint64_t published = 0;  // scans published so far
};

// What one read_new() returns.
struct ReadBatch {
  std::vector<CompensatedScan> scans;  // oldest first, consecutive in publish order
  std::uint64_t lost = 0;              // scans overwritten before this reader copied them
  std::uint64_t torn_reads = 0;        // copies discarded because the writer overwrote the slot
                                       // during the copy (each is also counted in lost)
  bool writer_restarted = false;       // the ring was re-created (new generation) since the last
                                       // read; scans now come from the new ring, from its oldest
};

// Totals since the reader was opened.
struct ReaderCounters {
  std::uint64_t scans_read = 0;
  std::uint64_t lost = 0;
  std::uint64_t torn_reads = 0;
  std::uint64_t writer_restarts = 0;
};

// The user tofcompd runs as (systemd/tofcompd.sysusers), whose rings readers accept by default.
inline constexpr const char* kDaemonUser = "tofcompd";

struct RingReaderOptions {
  // The users whose rings are read. Empty: this process's effective user, root, and the user
  // kDaemonUser when it exists.
  std::vector<uid_t> owners;
};

class RingReader {
 public:
  // Opens the ring `name` read-only and checks its owner and its header (magic, layout version,
  // byte order, sizes). Throws core::Error naming the object and what is wrong (including "does
  // not exist" and "belongs to"). The cursor starts at the next scan to be published.
  explicit RingReader(std::string name = kDefaultRingName, RingReaderOptions options = {});

  // The newest complete scan; nullopt while none was published. Retries copies torn by the
  // writer. Does not move the cursor.
  std::optional<CompensatedScan> latest();

  // The scans published since the cursor (at most max_scans), oldest first, and how many were
  // lost; moves the cursor past them. Returns at once, with no scans when there is nothing new.
  ReadBatch read_new(std::size_t max_scans = std::numeric_limits<std::size_t>::max());

  // Moves the cursor to the oldest scan still in the ring.
  void rewind_to_oldest();

  // Publish number (0, 1, ... in this ring) of the next scan read_new returns.
  std::uint64_t cursor() const { return cursor_; }

  RingInfo info() const;
  // The writer has not closed the ring and holds its lock (shm_object.hpp).
  bool writer_running() const;
  // The object read: the name asked for, or its alternative when that belonged to another user.
  const std::string& name() const { return name_; }
  // When the name asked for belonged to another user: that user.
  std::optional<uid_t> foreign_owner() const { return foreign_owner_; }
  const ReaderCounters& counters() const { return counters_; }

 private:
  // When the ring gets nothing new (or was closed), checks whether the name now refers to a ring
  // of another generation; if so maps it, with the cursor at its oldest scan, and returns true.
  bool follow_restart_if_idle(std::uint64_t published);
  std::uint64_t oldest_available(std::uint64_t published) const;
  const std::byte* slot(std::uint64_t publish_index) const;
  [[noreturn]] void throw_corrupt(std::uint64_t publish_index) const;

  // Throws core::Error when the object is now smaller than its header describes.
  void check_size() const;

  std::vector<uid_t> owners_;
  std::string name_;
  std::optional<uid_t> foreign_owner_;
  ShmMapping mapping_;
  RingGeometry geometry_;
  std::uint64_t generation_ = 0;
  std::uint64_t cursor_ = 0;
  std::uint64_t last_published_seen_ = 0;
  ReaderCounters counters_;
  CompensatedScan scratch_;
};

}  // namespace tofcomp::ipc::ring
