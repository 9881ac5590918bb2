// The ring's header in a mapping: the writer's initialisation, the atomic fields both sides
// read and write (magic, writer_state, published), and a reader's validation of the rest against
// the layout of this build (ring_layout.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "ipc/ring/ring_layout.hpp"
#include "ipc/ring/shm_object.hpp"

namespace tofcomp::ipc::ring {

// Writer: fills every field of a zero-filled header except the magic (set last by
// publish_magic, with release, so that a reader that sees the magic sees the rest).
void initialise_header(std::byte* base, const RingGeometry& geometry, std::int32_t writer_pid,
                       std::uint64_t generation);
void publish_magic(std::byte* base);

std::uint64_t load_magic(const std::byte* base);                 // acquire
std::uint32_t load_writer_state(const std::byte* base);          // acquire
void store_writer_state(std::byte* base, std::uint32_t state);   // release
std::uint64_t load_published(const std::byte* base);             // acquire
void store_published(std::byte* base, std::uint64_t published);  // release

// A copy of the header's fields (the atomic ones as loaded now).
RingHeader read_header(const std::byte* base);

// Whether the mapping holds a ring that its writer has not finished creating: too small for a
// header, or no magic yet.
bool ring_being_created(const ShmMapping& mapping);

// Checks the header of the ring in `mapping` (the object `name`): magic, layout version, byte
// order, header/slot/beam sizes, max_modes, counts within limits, object size. Throws core::Error
// naming the object and the mismatch; returns the ring's geometry.
RingGeometry validate_ring_header(const ShmMapping& mapping, const std::string& name);

}  // namespace tofcomp::ipc::ring
