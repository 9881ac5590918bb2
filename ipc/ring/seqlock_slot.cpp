// The per-slot sequence lock of the ring: see seqlock_slot.hpp. Every word of a slot is accessed
// through std::atomic_ref<std::uint64_t> (relaxed for the payload), so the concurrent copies of
// the writer and the readers are atomic accesses, not data races; the fences give the ordering.
#include "ipc/ring/seqlock_slot.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>

#include "ipc/ring/ring_layout.hpp"

namespace tofcomp::ipc::ring {

namespace {

static_assert(std::atomic_ref<std::uint64_t>::is_always_lock_free,
              "the ring needs lock-free 8-byte atomics (shared between processes)");

// The word at p, which is 8-byte aligned (the mapping is page aligned and every record is a
// multiple of 8 bytes). Readers only load through it, which is valid on a read-only mapping
// for a lock-free 8-byte atomic.
std::atomic_ref<std::uint64_t> word_at(const std::byte* p) {
  return std::atomic_ref<std::uint64_t>(
      *reinterpret_cast<std::uint64_t*>(const_cast<std::byte*>(p)));
}

void store_words(std::byte* destination, const void* source, std::size_t bytes) {
  const auto* from = static_cast<const unsigned char*>(source);
  for (std::size_t k = 0; k < bytes; k += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, from + k, 8);
    word_at(destination + k).store(word, std::memory_order_relaxed);
  }
}

void load_words(void* destination, const std::byte* source, std::size_t bytes) {
  auto* to = static_cast<unsigned char*>(destination);
  for (std::size_t k = 0; k < bytes; k += 8) {
    const std::uint64_t word = word_at(source + k).load(std::memory_order_relaxed);
    std::memcpy(to + k, &word, 8);
  }
}

// The slot header after its seq word.
constexpr std::size_t kSlotPayloadOffset = sizeof(std::uint64_t);

BeamRecord to_record(const BeamValue& beam) {
  BeamRecord r{};
  r.raw_mm = beam.raw_mm;
  r.compensated_mm = beam.compensated_mm;
  r.window_mm = beam.window_mm;
  r.window_std_mm = beam.window_std_mm;
  r.mode_posterior = beam.mode_posterior;
  r.flags = beam.flags;
  r.mode_count = beam.mode_count;
  r.most_probable_mode = beam.most_probable_mode;
  return r;
}

BeamValue from_record(const BeamRecord& r) {
  BeamValue beam;
  beam.raw_mm = r.raw_mm;
  beam.compensated_mm = r.compensated_mm;
  beam.window_mm = r.window_mm;
  beam.window_std_mm = r.window_std_mm;
  beam.mode_posterior = r.mode_posterior;
  beam.flags = r.flags;
  beam.mode_count = r.mode_count;
  beam.most_probable_mode = r.most_probable_mode;
  return beam;
}

}  // namespace

void write_slot(std::byte* slot, std::uint64_t publish_index, const CompensatedScan& scan) {
  const auto seq = word_at(slot);
  seq.store(complete_seq(publish_index) - 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);

  SlotHeader header{};
  header.sequence = scan.sequence;
  header.device_sequence = scan.device_sequence;
  header.timestamp_ns = scan.timestamp_ns;
  header.junction_c = scan.junction_c;
  header.junction_std_c = scan.junction_std_c;
  header.case_c = scan.case_c;
  header.start_angle_deg = scan.start_angle_deg;
  header.resolution_deg = scan.resolution_deg;
  header.calibration_id = scan.calibration_id;
  header.beam_count = static_cast<std::uint32_t>(scan.beams.size());
  header.first_ray_ns = scan.rays.first_ray_ns;
  header.ray_interval_ns = scan.rays.ray_interval_ns;
  header.turn_period_ns = scan.rays.turn_period_ns;
  header.interlaced_turns = scan.rays.interlaced_turns;
  store_words(slot + kSlotPayloadOffset,
              reinterpret_cast<const unsigned char*>(&header) + kSlotPayloadOffset,
              sizeof(SlotHeader) - kSlotPayloadOffset);
  std::byte* beam_at = slot + sizeof(SlotHeader);
  for (const BeamValue& beam : scan.beams) {
    const BeamRecord record = to_record(beam);
    store_words(beam_at, &record, sizeof(BeamRecord));
    beam_at += sizeof(BeamRecord);
  }

  seq.store(complete_seq(publish_index), std::memory_order_release);
}

SlotRead read_slot(const std::byte* slot, std::uint64_t publish_index, std::uint32_t max_beams,
                   CompensatedScan& out) {
  const auto seq = word_at(slot);
  const std::uint64_t expected = complete_seq(publish_index);
  const std::uint64_t before = seq.load(std::memory_order_acquire);
  if (before < expected) return SlotRead::kNotYetWritten;
  if (before > expected) return SlotRead::kOverwritten;

  SlotHeader header{};
  load_words(reinterpret_cast<unsigned char*>(&header) + kSlotPayloadOffset,
             slot + kSlotPayloadOffset, sizeof(SlotHeader) - kSlotPayloadOffset);
  // A torn header may carry any beam_count: copy at most max_beams, decide after the re-check.
  const std::uint32_t beams = std::min(header.beam_count, max_beams);
  out.beams.resize(beams);
  const std::byte* beam_at = slot + sizeof(SlotHeader);
  for (std::uint32_t b = 0; b < beams; ++b) {
    BeamRecord record{};
    load_words(&record, beam_at, sizeof(BeamRecord));
    out.beams[b] = from_record(record);
    beam_at += sizeof(BeamRecord);
  }

  std::atomic_thread_fence(std::memory_order_acquire);
  const std::uint64_t after = seq.load(std::memory_order_relaxed);
  if (after != before) return SlotRead::kTorn;
  if (header.beam_count > max_beams) return SlotRead::kCorrupt;

  out.sequence = header.sequence;
  out.device_sequence = header.device_sequence;
  out.timestamp_ns = header.timestamp_ns;
  out.junction_c = header.junction_c;
  out.junction_std_c = header.junction_std_c;
  out.case_c = header.case_c;
  out.start_angle_deg = header.start_angle_deg;
  out.resolution_deg = header.resolution_deg;
  out.calibration_id = header.calibration_id;
  out.rays = {header.first_ray_ns, header.ray_interval_ns, header.turn_period_ns,
              header.interlaced_turns};
  return SlotRead::kComplete;
}

}  // namespace tofcomp::ipc::ring
