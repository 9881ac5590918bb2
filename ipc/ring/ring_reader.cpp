// A reader of tofcompd's shared-memory ring: see ring_reader.hpp.
#include "ipc/ring/ring_reader.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"
#include "ipc/ring/ring_header.hpp"
#include "ipc/ring/seqlock_slot.hpp"

namespace tofcomp::ipc::ring {

namespace {

// latest() gives up after this many copies in a row lost to the writer: the writer would have
// to lap the whole ring during every one of them.
constexpr int kLatestAttempts = 1000;

ShmMapping open_ring(const std::string& name) {
  validate_shm_name(name);
  auto mapping = map_existing_read_only(name);
  if (!mapping) {
    throw core::Error(describe_object(name) + " does not exist (no /dev/shm" + name +
                      "): is its writer (tofcompd) "
                      "running, with this ring name?");
  }
  return std::move(*mapping);
}

}  // namespace

RingReader::RingReader(std::string name) : name_(std::move(name)), mapping_(open_ring(name_)) {
  geometry_ = validate_ring_header(mapping_, name_);
  generation_ = read_header(mapping_.data()).generation;
  last_published_seen_ = load_published(mapping_.data());
  cursor_ = last_published_seen_;
}

const std::byte* RingReader::slot(std::uint64_t publish_index) const {
  return mapping_.data() + geometry_.slot_offset(publish_index);
}

std::uint64_t RingReader::oldest_available(std::uint64_t published) const {
  return published > geometry_.slot_count ? published - geometry_.slot_count : 0;
}

void RingReader::throw_corrupt(std::uint64_t publish_index) const {
  throw core::Error(describe_object(name_) + ": slot of publish " + std::to_string(publish_index) +
                    " claims more than the ring's max_beams (" +
                    std::to_string(geometry_.max_beams) + ") beams: the ring is corrupt");
}

bool RingReader::follow_restart_if_idle(std::uint64_t published) {
  const bool idle = published == last_published_seen_;
  if (!idle && load_writer_state(mapping_.data()) != kWriterClosed) return false;
  const auto now = identify_object(name_);
  if (!now || *now == mapping_.id()) return false;
  auto fresh = map_existing_read_only(name_);
  if (!fresh || ring_being_created(*fresh)) return false;  // try again at the next read
  const RingGeometry geometry = validate_ring_header(*fresh, name_);
  const std::uint64_t generation = read_header(fresh->data()).generation;
  if (generation == generation_) return false;
  mapping_ = std::move(*fresh);
  geometry_ = geometry;
  generation_ = generation;
  const std::uint64_t fresh_published = load_published(mapping_.data());
  cursor_ = oldest_available(fresh_published);
  last_published_seen_ = fresh_published;
  ++counters_.writer_restarts;
  return true;
}

std::optional<CompensatedScan> RingReader::latest() {
  follow_restart_if_idle(load_published(mapping_.data()));
  for (int attempt = 0; attempt < kLatestAttempts; ++attempt) {
    const std::uint64_t published = load_published(mapping_.data());
    last_published_seen_ = published;
    if (published == 0) return std::nullopt;
    const std::uint64_t newest = published - 1;
    switch (read_slot(slot(newest), newest, geometry_.max_beams, scratch_)) {
      case SlotRead::kComplete:
        return scratch_;
      case SlotRead::kTorn:
        ++counters_.torn_reads;
        break;
      case SlotRead::kCorrupt:
        throw_corrupt(newest);
      case SlotRead::kOverwritten:
      case SlotRead::kNotYetWritten:
        break;
    }
  }
  throw core::Error(describe_object(name_) + ": no consistent copy of the newest scan in " +
                    std::to_string(kLatestAttempts) +
                    " attempts: the writer laps the ring faster than a scan can be copied");
}

ReadBatch RingReader::read_new(std::size_t max_scans) {
  ReadBatch batch;
  std::uint64_t published = load_published(mapping_.data());
  if (follow_restart_if_idle(published)) {
    batch.writer_restarted = true;
    published = load_published(mapping_.data());
  }
  last_published_seen_ = published;
  cursor_ = std::min(cursor_, published);
  const auto skip_overwritten = [&](std::uint64_t now_published) {
    const std::uint64_t oldest = oldest_available(now_published);
    if (cursor_ < oldest) {
      batch.lost += oldest - cursor_;
      cursor_ = oldest;
    }
  };
  skip_overwritten(published);
  batch.scans.reserve(
      static_cast<std::size_t>(std::min<std::uint64_t>(published - cursor_, max_scans)));
  while (cursor_ < published && batch.scans.size() < max_scans) {
    // Copied straight into the batch; a failed copy is dropped again.
    CompensatedScan& copy = batch.scans.emplace_back();
    const SlotRead outcome = read_slot(slot(cursor_), cursor_, geometry_.max_beams, copy);
    if (outcome != SlotRead::kComplete) batch.scans.pop_back();
    switch (outcome) {
      case SlotRead::kComplete:
        ++cursor_;
        break;
      case SlotRead::kTorn:
        ++batch.torn_reads;
        [[fallthrough]];
      case SlotRead::kOverwritten:
        // The writer has lapped the cursor: this scan is gone, and maybe more after it.
        ++batch.lost;
        ++cursor_;
        skip_overwritten(load_published(mapping_.data()));
        break;
      case SlotRead::kNotYetWritten:
        // Cannot happen below `published` (released after the slot); end the batch if it does.
        published = cursor_;
        break;
      case SlotRead::kCorrupt:
        throw_corrupt(cursor_);
    }
  }
  counters_.scans_read += batch.scans.size();
  counters_.lost += batch.lost;
  counters_.torn_reads += batch.torn_reads;
  return batch;
}

void RingReader::rewind_to_oldest() {
  cursor_ = oldest_available(load_published(mapping_.data()));
}

RingInfo RingReader::info() const {
  const RingHeader h = read_header(mapping_.data());
  RingInfo info;
  info.name = name_;
  info.layout_version = h.layout_version;
  info.slot_count = h.slot_count;
  info.max_beams = h.max_beams;
  info.max_modes = h.max_modes;
  info.slot_size = h.slot_size;
  info.writer_pid = h.writer_pid;
  info.generation = h.generation;
  info.writer_closed = h.writer_state == kWriterClosed;
  info.published = h.published;
  return info;
}

bool RingReader::writer_running() const {
  const RingHeader h = read_header(mapping_.data());
  return h.writer_state != kWriterClosed && process_runs(h.writer_pid);
}

}  // namespace tofcomp::ipc::ring
