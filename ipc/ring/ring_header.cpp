// The ring's header in a mapping: see ring_header.hpp.
#include "ipc/ring/ring_header.hpp"

#include <atomic>
#include <cstdio>

#include "core/error.hpp"

namespace tofcomp::ipc::ring {

namespace {

RingHeader* header_at(std::byte* base) {
  return reinterpret_cast<RingHeader*>(base);
}

// Readers only load through these references (valid on a read-only mapping for lock-free
// atomics of 4 and 8 bytes).
template <class T>
std::atomic_ref<T> atomic_field(const std::byte* base, T RingHeader::*field) {
  return std::atomic_ref<T>(header_at(const_cast<std::byte*>(base))->*field);
}

std::string hex(std::uint64_t value) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace

void initialise_header(std::byte* base, const RingGeometry& geometry, std::int32_t writer_pid,
                       std::uint64_t generation) {
  RingHeader* h = header_at(base);
  h->layout_version = kLayoutVersion;
  h->endian_check = kEndianCheck;
  h->header_size = sizeof(RingHeader);
  h->slot_size = static_cast<std::uint32_t>(geometry.slot_size());
  h->slot_count = geometry.slot_count;
  h->max_beams = geometry.max_beams;
  h->max_modes = kMaxModes;
  h->slot_header_size = sizeof(SlotHeader);
  h->beam_record_size = sizeof(BeamRecord);
  h->writer_pid = writer_pid;
  h->generation = generation;
  atomic_field(base, &RingHeader::writer_state).store(kWriterAlive, std::memory_order_relaxed);
  atomic_field(base, &RingHeader::published).store(0, std::memory_order_relaxed);
}

void publish_magic(std::byte* base) {
  atomic_field(base, &RingHeader::magic).store(kRingMagic, std::memory_order_release);
}

std::uint64_t load_magic(const std::byte* base) {
  return atomic_field(base, &RingHeader::magic).load(std::memory_order_acquire);
}

std::uint32_t load_writer_state(const std::byte* base) {
  return atomic_field(base, &RingHeader::writer_state).load(std::memory_order_acquire);
}

void store_writer_state(std::byte* base, std::uint32_t state) {
  atomic_field(base, &RingHeader::writer_state).store(state, std::memory_order_release);
}

std::uint64_t load_published(const std::byte* base) {
  return atomic_field(base, &RingHeader::published).load(std::memory_order_acquire);
}

void store_published(std::byte* base, std::uint64_t published) {
  atomic_field(base, &RingHeader::published).store(published, std::memory_order_release);
}

RingHeader read_header(const std::byte* base) {
  RingHeader copy{};
  copy.magic = load_magic(base);
  const RingHeader* h = reinterpret_cast<const RingHeader*>(base);
  copy.layout_version = h->layout_version;
  copy.endian_check = h->endian_check;
  copy.header_size = h->header_size;
  copy.slot_size = h->slot_size;
  copy.slot_count = h->slot_count;
  copy.max_beams = h->max_beams;
  copy.max_modes = h->max_modes;
  copy.slot_header_size = h->slot_header_size;
  copy.beam_record_size = h->beam_record_size;
  copy.writer_pid = h->writer_pid;
  copy.generation = h->generation;
  copy.writer_state = load_writer_state(base);
  copy.published = load_published(base);
  return copy;
}

bool ring_being_created(const ShmMapping& mapping) {
  return mapping.size() < sizeof(RingHeader) || load_magic(mapping.data()) == 0;
}

RingGeometry validate_ring_header(const ShmMapping& mapping, const std::string& name) {
  const std::string what = describe_object(name);
  const auto fail = [&](const std::string& why) { throw core::Error(what + ": " + why); };
  if (mapping.size() < sizeof(RingHeader)) {
    fail("is " + std::to_string(mapping.size()) + " bytes, smaller than the " +
         std::to_string(sizeof(RingHeader)) +
         "-byte ring header (its writer has not finished creating it, or it is not a ring)");
  }
  const RingHeader h = read_header(mapping.data());
  if (h.magic == 0) fail("has no magic yet: its writer has not finished creating it");
  if (h.magic != kRingMagic) {
    fail("magic is " + hex(h.magic) + ", expected " + hex(kRingMagic) +
         " (\"TOFCRING\"): not a tofcomp ring");
  }
  if (h.layout_version != kLayoutVersion) {
    fail("layout version is " + std::to_string(h.layout_version) + ", this reader reads version " +
         std::to_string(kLayoutVersion));
  }
  if (h.endian_check != kEndianCheck) {
    fail("endian_check is " + hex(h.endian_check) + ", expected " + hex(kEndianCheck) +
         ": written with another byte order");
  }
  const auto expect = [&](const std::string& field, std::uint64_t found, std::uint64_t wanted) {
    if (found != wanted) {
      fail(field + " is " + std::to_string(found) + ", expected " + std::to_string(wanted));
    }
  };
  expect("header_size", h.header_size, sizeof(RingHeader));
  expect("slot_header_size", h.slot_header_size, sizeof(SlotHeader));
  expect("beam_record_size", h.beam_record_size, sizeof(BeamRecord));
  expect("max_modes", h.max_modes, kMaxModes);
  if (h.slot_count < kMinSlotCount || h.slot_count > kMaxSlotCount) {
    fail("slot_count is " + std::to_string(h.slot_count) + ", outside " +
         std::to_string(kMinSlotCount) + ".." + std::to_string(kMaxSlotCount));
  }
  if (h.max_beams < 1 || h.max_beams > kMaxBeamsLimit) {
    fail("max_beams is " + std::to_string(h.max_beams) + ", outside 1.." +
         std::to_string(kMaxBeamsLimit));
  }
  const RingGeometry geometry{h.slot_count, h.max_beams};
  expect("slot_size (for max_beams " + std::to_string(h.max_beams) + ")", h.slot_size,
         geometry.slot_size());
  if (geometry.ring_size() > mapping.size()) {
    fail("is " + std::to_string(mapping.size()) + " bytes, but its header describes " +
         std::to_string(geometry.ring_size()) + " bytes (" + std::to_string(h.slot_count) +
         " slots of " + std::to_string(h.slot_size) + ")");
  }
  return geometry;
}

}  // namespace tofcomp::ipc::ring
