// The binary layout of the shared-memory ring through which tofcompd publishes each compensated
// scan (docs/shm-ring.md is the reference for readers in other languages and must match this
// file field by field). One header of 128 bytes, then slot_count slots of slot_size bytes each;
// a slot is a slot header of 112 bytes followed by max_beams beam records of 56 bytes.
// All integers and doubles are little-endian (the host's order; asserted below and recorded in
// the header's endian_check). Fields marked "atomic" are read and written with atomic
// operations; the others of the header never change once the magic is set.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "ipc/compensated_scan.hpp"

namespace tofcomp::ipc::ring {

static_assert(std::endian::native == std::endian::little,
              "the ring layout is little-endian: a big-endian host would need byte swapping");

// "TOFCRING" in memory order: the 8 bytes at offset 0 of a tofcomp ring.
inline constexpr std::array<char, 8> kRingMagicBytes{'T', 'O', 'F', 'C', 'R', 'I', 'N', 'G'};
inline constexpr std::uint64_t kRingMagic = 0x474E495243464F54ull;  // the bytes above, as LE u64
// 2: the slot header carries the rays' timing (first_ray_ns .. interlaced_turns).
inline constexpr std::uint32_t kLayoutVersion = 2;
inline constexpr std::uint32_t kEndianCheck = 0x01020304u;  // bytes 04 03 02 01 on a LE host

// Values of RingHeader::writer_state.
inline constexpr std::uint32_t kWriterAlive = 1;   // a writer has the ring open
inline constexpr std::uint32_t kWriterClosed = 2;  // its writer closed it; it gets no more scans

// Limits the writer enforces and readers check.
inline constexpr std::uint32_t kMinSlotCount = 2;
inline constexpr std::uint32_t kMaxSlotCount = 1u << 20;
inline constexpr std::uint32_t kMaxBeamsLimit = 65535;
inline constexpr std::uint64_t kMaxRingBytes = 1ull << 30;  // 1 GiB

inline constexpr const char* kDefaultRingName = "/tofcompd";
inline constexpr std::uint32_t kDefaultMaxBeams = 1024;  // the LMS 200 sends at most 721 values
inline constexpr std::uint32_t kDefaultSlotCount = 64;   // 0.85 s of scans at 75 scans/s

struct RingHeader {
  std::uint64_t magic;             // 0: kRingMagic; stored last (release) by the writer
  std::uint32_t layout_version;    // 8: kLayoutVersion
  std::uint32_t endian_check;      // 12: kEndianCheck
  std::uint32_t header_size;       // 16: sizeof(RingHeader) = 128, offset of slot 0
  std::uint32_t slot_size;         // 20: bytes from one slot to the next
  std::uint32_t slot_count;        // 24
  std::uint32_t max_beams;         // 28: beam records per slot
  std::uint32_t max_modes;         // 32: kMaxModes, the mode_posterior entries per beam
  std::uint32_t slot_header_size;  // 36: sizeof(SlotHeader) = 112, offset of beam 0 in a slot
  std::uint32_t beam_record_size;  // 40: sizeof(BeamRecord) = 56
  std::int32_t writer_pid;         // 44: process id of the writer
  std::uint64_t generation;        // 48: unique per creation of the ring (see docs)
  std::uint32_t writer_state;      // 56: atomic; kWriterAlive or kWriterClosed
  std::uint32_t reserved0;         // 60: 0
  std::uint64_t published;         // 64: atomic; scans published so far (next publish index)
  std::array<std::uint8_t, 56> reserved1;  // 72: 0
};

struct SlotHeader {
  std::uint64_t seq;              // 0: atomic seqlock; 2i+1 while publish i is written, 2i+2
                                  //    once it is complete, 0 before the first
  std::uint64_t sequence;         // 8: CompensatedScan::sequence
  std::uint64_t device_sequence;  // 16
  std::int64_t timestamp_ns;      // 24
  double junction_c;              // 32
  double junction_std_c;          // 40
  double case_c;                  // 48
  double start_angle_deg;         // 56
  double resolution_deg;          // 64
  std::uint32_t calibration_id;   // 72
  std::uint32_t beam_count;       // 76: beam records in use, <= max_beams
  std::int64_t first_ray_ns;      // 80: CompensatedScan::rays (core/ray_timing.hpp)
  double ray_interval_ns;         // 88
  double turn_period_ns;          // 96
  std::uint32_t interlaced_turns;  // 104: 0 when the timing is unknown
  std::uint32_t reserved;          // 108: 0
};

struct BeamRecord {
  double raw_mm;                                // 0
  double compensated_mm;                        // 8
  double window_mm;                             // 16
  double window_std_mm;                         // 24
  std::array<float, kMaxModes> mode_posterior;  // 32
  std::uint16_t flags;                          // 48: BeamFlag bits
  std::uint8_t mode_count;                      // 50
  std::uint8_t most_probable_mode;              // 51
  std::uint32_t reserved;                       // 52: 0
};

static_assert(std::is_standard_layout_v<RingHeader> && std::is_trivially_copyable_v<RingHeader>);
static_assert(std::is_standard_layout_v<SlotHeader> && std::is_trivially_copyable_v<SlotHeader>);
static_assert(std::is_standard_layout_v<BeamRecord> && std::is_trivially_copyable_v<BeamRecord>);

static_assert(sizeof(RingHeader) == 128);
static_assert(offsetof(RingHeader, magic) == 0);
static_assert(offsetof(RingHeader, layout_version) == 8);
static_assert(offsetof(RingHeader, endian_check) == 12);
static_assert(offsetof(RingHeader, header_size) == 16);
static_assert(offsetof(RingHeader, slot_size) == 20);
static_assert(offsetof(RingHeader, slot_count) == 24);
static_assert(offsetof(RingHeader, max_beams) == 28);
static_assert(offsetof(RingHeader, max_modes) == 32);
static_assert(offsetof(RingHeader, slot_header_size) == 36);
static_assert(offsetof(RingHeader, beam_record_size) == 40);
static_assert(offsetof(RingHeader, writer_pid) == 44);
static_assert(offsetof(RingHeader, generation) == 48);
static_assert(offsetof(RingHeader, writer_state) == 56);
static_assert(offsetof(RingHeader, reserved0) == 60);
static_assert(offsetof(RingHeader, published) == 64);
static_assert(offsetof(RingHeader, reserved1) == 72);

static_assert(sizeof(SlotHeader) == 112);
static_assert(offsetof(SlotHeader, seq) == 0);
static_assert(offsetof(SlotHeader, sequence) == 8);
static_assert(offsetof(SlotHeader, device_sequence) == 16);
static_assert(offsetof(SlotHeader, timestamp_ns) == 24);
static_assert(offsetof(SlotHeader, junction_c) == 32);
static_assert(offsetof(SlotHeader, junction_std_c) == 40);
static_assert(offsetof(SlotHeader, case_c) == 48);
static_assert(offsetof(SlotHeader, start_angle_deg) == 56);
static_assert(offsetof(SlotHeader, resolution_deg) == 64);
static_assert(offsetof(SlotHeader, calibration_id) == 72);
static_assert(offsetof(SlotHeader, beam_count) == 76);
static_assert(offsetof(SlotHeader, first_ray_ns) == 80);
static_assert(offsetof(SlotHeader, ray_interval_ns) == 88);
static_assert(offsetof(SlotHeader, turn_period_ns) == 96);
static_assert(offsetof(SlotHeader, interlaced_turns) == 104);
static_assert(offsetof(SlotHeader, reserved) == 108);

static_assert(sizeof(BeamRecord) == 56);
static_assert(offsetof(BeamRecord, raw_mm) == 0);
static_assert(offsetof(BeamRecord, compensated_mm) == 8);
static_assert(offsetof(BeamRecord, window_mm) == 16);
static_assert(offsetof(BeamRecord, window_std_mm) == 24);
static_assert(offsetof(BeamRecord, mode_posterior) == 32);
static_assert(offsetof(BeamRecord, flags) == 48);
static_assert(offsetof(BeamRecord, mode_count) == 50);
static_assert(offsetof(BeamRecord, most_probable_mode) == 51);
static_assert(offsetof(BeamRecord, reserved) == 52);

// Every field is copied as 8-byte words (see seqlock_slot.hpp).
static_assert(sizeof(SlotHeader) % 8 == 0 && sizeof(BeamRecord) % 8 == 0);
static_assert(sizeof(double) == 8 && sizeof(float) == 4);

// Bytes of one slot for max_beams beams: slot header and beam records, rounded up to a multiple
// of 64 so that every slot starts on a cache line.
constexpr std::uint64_t slot_size_for(std::uint32_t max_beams) {
  const std::uint64_t used = sizeof(SlotHeader) + std::uint64_t{max_beams} * sizeof(BeamRecord);
  return (used + 63) / 64 * 64;
}

constexpr std::uint64_t ring_size_for(std::uint32_t slot_count, std::uint32_t max_beams) {
  return sizeof(RingHeader) + std::uint64_t{slot_count} * slot_size_for(max_beams);
}

static_assert(slot_size_for(1024) == 57472);
static_assert(slot_size_for(361) == 20352);

// Where the slots of a ring are, from its header's counts.
struct RingGeometry {
  std::uint32_t slot_count = 0;
  std::uint32_t max_beams = 0;

  std::uint64_t slot_size() const { return slot_size_for(max_beams); }
  std::uint64_t ring_size() const { return ring_size_for(slot_count, max_beams); }
  // Byte offset of the slot that publish number `publish_index` (0, 1, ...) goes to.
  std::uint64_t slot_offset(std::uint64_t publish_index) const {
    return sizeof(RingHeader) + (publish_index % slot_count) * slot_size();
  }
};

}  // namespace tofcomp::ipc::ring
