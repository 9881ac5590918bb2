// The per-slot sequence lock of the ring: the writer's copy of a scan into a slot and a reader's
// copy out of it, as 8-byte relaxed atomic words bracketed by the slot's seq word.
// Writer of publish i: seq = 2i+1 (relaxed), release fence, payload, seq = 2i+2 (release).
// Reader of publish i: s1 = seq (acquire); s1 must be 2i+2; payload; acquire fence; s2 = seq
// (relaxed); the copy is good only if s2 == s1. The writer never waits; a reader that loses the
// race sees s2 != s1 and discards its copy.
#pragma once

#include <cstddef>
#include <cstdint>

#include "ipc/compensated_scan.hpp"

namespace tofcomp::ipc::ring {

// seq of a slot that holds publish i completely.
constexpr std::uint64_t complete_seq(std::uint64_t publish_index) {
  return 2 * publish_index + 2;
}

// Copies scan into `slot` as publish number publish_index. scan.beams.size() must not exceed the
// ring's max_beams (the caller checks).
void write_slot(std::byte* slot, std::uint64_t publish_index, const CompensatedScan& scan);

enum class SlotRead {
  kComplete,       // `out` holds publish i, consistent
  kNotYetWritten,  // the slot does not hold publish i yet
  kOverwritten,    // the writer had already replaced publish i by a later one
  kTorn,           // the writer replaced publish i during the copy; `out` is garbage
  kCorrupt,        // consistent, but its beam_count exceeds max_beams: not a valid ring
};

// Copies publish number publish_index out of `slot` into `out` (its beams are resized; their
// storage is reused). `slot` may be in read-only memory.
SlotRead read_slot(const std::byte* slot, std::uint64_t publish_index, std::uint32_t max_beams,
                   CompensatedScan& out);

}  // namespace tofcomp::ipc::ring
